// The meshless precomputation on disk: the basis points, S and the
// statistics, saved after a solve and reloaded by a later solve of the same scene, so that
// reopening a file and relighting costs no precompute. The R-trees and the DAG are rebuilt
// from the points on load (BasisHierarchy's constructor), which is a small part of the
// precompute and keeps the file small.
//
// A file is named by its key, a 128-bit hash of everything that shapes the precomputation:
// the cache format and library versions, the scene's textures, materials and meshes (the
// .bgs encoding of them; lights and world do not shape it), the settings that were used
// except those a caller names (the relight settings, threads, ...), and the bake points when
// they placed the basis. Layout, all little-endian (util/byte_stream.h):
//   header   "BAKEGI\0M", u32 format version, u32 reserved (0), u64 key high, u64 key low,
//            u64 payload bytes
//   payload  sections, each u32 tag, u32 reserved (0), u64 bytes, then its data, in order:
//            STAT statistics, PNTS basis points (sorted by level), XFER S per channel (CSC)
//   trailer  u64 FNV-1a 64 of header and payload
// Reading checks the version, the full key, every size against the bytes left and the
// checksum before it allocates or trusts anything; any mismatch is an Error(BAD_FILE) that
// says why, and the caller rebuilds.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "scene/bake_points.h"
#include "scene/scene.h"
#include "solvers/meshless/meshless_precomputation.h"
#include "settings/settings.h"

namespace bakegi {
class JobContext;
}

namespace bakegi::meshless {

// Bump when the layout changes or when what the precomputation computes changes (placement,
// refinement, bounces) so that files made by older code are never loaded.
// 2: glossy lobes fold into T; 3: levels_reduced in the statistics; 4: the senders' sky
// visibility (SKYV); 5: gather hits complete blind sender levels, and the receivers' coarser
// relations (RREL) for completing them at bake points.
inline constexpr uint32_t kPrecomputationCacheVersion = 5;

struct CacheKey {
  uint64_t high = 0, low = 0;
  bool operator==(const CacheKey&) const = default;
  // "meshless-<16 hex digits of high>.bgcache"
  std::string file_name() const;
};

// `ignored_settings`: keys left out of the key (they do not shape the precomputation).
// `placement_points`: the bake points when they placed the basis, else null.
CacheKey precomputation_key(const SceneDescription& scene,
                            const std::map<std::string, SettingValue>& used_settings,
                            const std::vector<std::string>& ignored_settings,
                            const BakePoints* placement_points);

std::vector<uint8_t> encode_precomputation(const MeshlessPrecomputation& precomputation,
                                           const CacheKey& key);

// Throws Error(BAD_FILE), prefixed by `name`, when the bytes are not a cache file of this
// version and key ("stale") or are damaged ("corrupt"). `job` (optional) is checked for
// cancel while the basis is rebuilt.
std::shared_ptr<MeshlessPrecomputation> decode_precomputation(std::span<const uint8_t> bytes,
                                                              const CacheKey& expected,
                                                              const std::string& name,
                                                              const JobContext* job = nullptr);

}  // namespace bakegi::meshless
