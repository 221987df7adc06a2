// The meshless precomputation as a cache payload (bake/precomputation_store.h writes the
// file around it: key, header, checksum): the basis points, S and the statistics. The
// R-trees and the DAG are rebuilt from the points on load (BasisHierarchy's constructor),
// which is a small part of the precompute and keeps the file small. Sections, each u32 tag,
// u32 reserved (0), u64 bytes, then its data, in order: STAT statistics, PNTS basis points
// (sorted by level), XFER S per channel (CSC), SKYV the senders' sky visibility, RREL the
// receivers' coarser relations. Every count is checked against the bytes left before
// anything is allocated for it.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "solvers/meshless/meshless_precomputation.h"

namespace bakegi {
class ByteReader;
class ByteWriter;
class JobContext;
}  // namespace bakegi

namespace bakegi::meshless {

// Bump when the layout changes or when what the precomputation computes changes (placement,
// refinement, bounces) so that files made by older code are never loaded.
// 2: glossy lobes fold into T; 3: levels_reduced in the statistics; 4: the senders' sky
// visibility (SKYV); 5: gather hits complete blind sender levels, and the receivers' coarser
// relations (RREL) for completing them at bake points.
inline constexpr uint32_t kPrecomputationCacheVersion = 7;

void encode_precomputation(const MeshlessPrecomputation& precomputation, ByteWriter& payload);

// Throws Error(BAD_FILE) through `payload` when the sections are inconsistent. `job`
// (optional) is checked for cancel while the basis is rebuilt.
std::shared_ptr<MeshlessPrecomputation> decode_precomputation(ByteReader& payload,
                                                              const JobContext* job = nullptr);

}  // namespace bakegi::meshless
