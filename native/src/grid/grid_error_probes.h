// Where a grid bake checks its own error (bake/error_estimate.h), so that a grid whose light
// is far off is flagged rather than trusted: probes on the scene's surfaces inside the grid's
// box, drawn by area (a surface counts as much as it is large, as the meshes Apply Grid lights
// would sample it), each with its triangle's shading normal. Probe i's stencil is value i of
// the grid's reading at the probes.
#pragma once

#include <cstddef>
#include <cstdint>

#include "bake/error_probes.h"
#include "grid/grid_layout.h"

namespace bakegi {

struct Scene;

// At most `count` probes (fewer when little surface lies in the box: up to 32 draws a probe).
// Deterministic for a seed.
ErrorProbes grid_surface_probes(const Scene& scene, const GridLayout& layout, size_t count,
                                uint64_t seed);

}  // namespace bakegi
