// Which lightmap texel samples may share one value (issue 15, item 3: do no work twice).
//
// The rasterizer makes one sample per (texel, triangle) overlap, so a texel crossed by the
// edges of a mesh's triangles holds several samples, one on each triangle, all within the
// texel's footprint on the same surface: a dense mesh under a coarse lightmap bakes many
// samples per texel, and the texel's value is their weighted mean anyway. Here each sample
// names the first earlier sample of its texel (BakePoints::share_candidates) that has the
// same normal (kSharedNormalCosine) and lies within kTexelShareFootprints of the texel's footprint,
// measured as the distance to the first sample of a neighbouring texel on the same surface.
// Samples of one texel from unrelated parts of the mesh (two charts packed against each
// other, a crease) stay apart; bake/point_sharing.h then also checks that nothing stands
// between the two (a wall on the surface).
#pragma once

#include <cstdint>
#include <vector>

#include "lightmap/texel_rasterizer.h"

namespace bakegi {

// Samples that far apart, in texel steps, are one texel's (a texel's diagonal is 1.41).
inline constexpr float kTexelShareFootprints = 1.5f;

// Per sample of `samples`, its share candidate, as an index offset by `first_index` (the
// index of samples' first point among the bake points): the first sample of its group,
// which names itself.
std::vector<uint32_t> texel_share_candidates(const TexelSamples& samples, uint64_t first_index);

}  // namespace bakegi
