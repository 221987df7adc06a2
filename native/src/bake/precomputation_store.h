// The job's cache of precomputations on disk: a method whose solver has a codec
// (solvers/precomputation_codec.h) and a "cache_dir" setting gets its precomputation saved
// after a full bake and loaded by a later bake of the same scene, so that reopening a file
// and relighting costs no precompute.
//
// A file is named by its key, a 128-bit hash of everything that shapes the precomputation:
// the codec's version, the library version, the scene's textures, materials and meshes (the
// .bgs encoding of them; lights and world do not shape it), the settings that were used
// except those whose role is lighting or execution, and the bake points when they shaped it.
// Layout, all little-endian (util/byte_stream.h):
//   header   "BAKEGI\0" + the codec's magic byte, u32 codec version, u32 reserved (0),
//            u64 key high, u64 key low, u64 payload bytes
//   payload  what the codec writes (sections)
//   trailer  u64 FNV-1a 64 of header and payload
// Reading checks the version, the full key, every size against the bytes left and the
// checksum before it allocates or trusts anything; any mismatch is an Error(BAD_FILE) that
// says why, and the job rebuilds (report "<name>_cache": "stale", with a warning).
// Meshless files (magic 'M') made before the store existed have this layout and key.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "scene/bake_points.h"
#include "scene/scene.h"
#include "settings/setting_schema.h"
#include "settings/settings.h"
#include "solvers/precomputation_codec.h"

namespace bakegi {

class JobContext;
class Precomputation;

struct CacheKey {
  uint64_t high = 0, low = 0;
  bool operator==(const CacheKey&) const = default;
  // "<codec name>-<16 hex digits of high>.bgcache"
  std::string file_name(const std::string& codec_name) const;
};

// `ignored_settings`: keys left out of the key (they do not shape the precomputation).
// `placement_points`: the bake points when they shaped the precomputation, else null.
CacheKey precomputation_key(uint32_t codec_version, const SceneDescription& scene,
                            const std::map<std::string, SettingValue>& used_settings,
                            const std::vector<std::string>& ignored_settings,
                            const BakePoints* placement_points);

std::vector<uint8_t> encode_cache_file(const PrecomputationCodec& codec,
                                       const Precomputation& precomputation, const CacheKey& key);

// Throws Error(BAD_FILE), prefixed by `name`, when the bytes are not a cache file of this
// codec, version and key ("stale") or are damaged ("corrupt").
std::shared_ptr<const Precomputation> decode_cache_file(const PrecomputationCodec& codec,
                                                        std::span<const uint8_t> bytes,
                                                        const CacheKey& expected,
                                                        const std::string& name,
                                                        const JobContext* job = nullptr);

// The "cache_max_mb" setting of every method with a "cache_dir": the folder's size cap.
SettingSpec cache_size_setting();

struct CacheRequest {
  const PrecomputationCodec& codec;
  std::string folder;  // UTF-8; created when missing
  const SceneDescription& scene;
  const Settings& settings;  // the used ones key the file
  std::vector<std::string> ignored_settings;
  const BakePoints* points = nullptr;  // the bake points, keyed when the codec says so
  uint64_t max_file_bytes = 0;         // a file larger than this is not read
  uint64_t max_folder_bytes = 0;       // cache files beyond this are evicted; 0 = no cap
};

// Keeps the cache files ("*.bgcache") of `folder` within `max_bytes` by deleting the least
// recently used (oldest modification time: a hit touches its file), never `keep`. Errors
// (another process deleting the same file) are ignored. Returns how many were deleted.
size_t evict_least_recently_used(const std::string& folder, uint64_t max_bytes,
                                 const std::string& keep);

// Loads the precomputation `request` keys, or makes it with `make` and saves it (then evicts
// beyond max_folder_bytes). Reports "<name>_cache" (hit, miss, stale), "<name>_cache_path",
// the seconds and bytes, "<name>_cache_evicted"; a file that
// cannot be saved is a warning, never a failed bake.
std::shared_ptr<const Precomputation> load_or_precompute(
    const CacheRequest& request, JobContext& context,
    const std::function<std::shared_ptr<const Precomputation>()>& make);

}  // namespace bakegi
