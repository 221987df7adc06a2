// The antiradiance precomputation as a cache payload (bake/precomputation_store.h writes the
// file around it: key, header, checksum): the element hierarchy, the links and the statistics,
// what precompute() takes seconds to make. Bins and spreading tables are a deterministic
// function of the "bins" setting (its Nside) and take milliseconds: they are rebuilt on load,
// not stored. Sections, each u32 tag, u32 reserved (0), u64 bytes, then its data, in order:
// STAT Nside, seconds, link statistics and warnings; HIER the hierarchy's scalars; ELEM the
// elements (pre-order); PTCH the patches (leaf order); MEMB the member triangles of merged
// patches; LINK the receivers' offsets and the links in the global pass' order (grouped by
// receiver, which the offsets imply and the file leaves out). Every count is checked against
// the bytes left before anything is allocated for it, and every index against what it
// indexes.
#pragma once

#include <cstdint>
#include <memory>

#include "solvers/antiradiance/antiradiance_precomputation.h"

namespace bakegi {
class ByteReader;
class ByteWriter;
class JobContext;
}  // namespace bakegi

namespace bakegi::antiradiance {

// Bump when the layout changes or when what the precomputation computes changes (patches,
// grouping, back sides, linking, the oracle, form factors, the link order) so that files made
// by older code are never loaded.
inline constexpr uint32_t kPrecomputationCacheVersion = 1;

void encode_precomputation(const AntiradiancePrecomputation& precomputation, ByteWriter& payload);

// Throws Error(BAD_FILE) through `payload` when the sections are inconsistent. `job`
// (optional) is checked for cancel after the bins are rebuilt.
std::shared_ptr<AntiradiancePrecomputation> decode_precomputation(ByteReader& payload,
                                                                  const JobContext* job = nullptr);

}  // namespace bakegi::antiradiance
