// Where on each emissive triangle its light comes from, for light sampling: a triangle
// whose emission is multiplied by a texture is split into cells (triangle_cells.h) about
// kTexelsPerCell texels of its UV footprint each, and every cell gets the mean of its
// emitted radiance (material emission x texture), estimated once when the scene is built.
// Light sampling then picks cells by power, so a mostly black texture (a screen showing a
// small logo) does not spend its samples on black. Untextured emitters are one cell whose
// power is their emission, exactly as before textures existed.
//
// The means only steer sampling: emitted radiance is always looked up at the sampled point,
// so an estimate that is off changes noise, not the result. Bounded (EmissionCellLimits):
// levels and quadrature shrink evenly so that the whole scene's cells and texture lookups
// fit, and a huge textured emitter cannot stall a bake or fill memory.
#pragma once

#include <cstdint>
#include <vector>

namespace bakegi {

struct Scene;

struct EmissionCells {
  // Per entry of Scene::emissive_triangles: its subdivision level (level² cells) and the
  // index of its first cell in `power` (one more entry at the end: the total).
  std::vector<uint32_t> level;
  std::vector<uint64_t> first;
  // Per cell: mean emitted radiance summed over R, G and B (W/(m² sr)).
  std::vector<float> power;
  uint64_t lookups = 0;  // texture lookups made to estimate them

  static constexpr double kTexelsPerCell = 4.0;  // about 2 x 2 texels
  static constexpr uint32_t kMaxLevel = 64;      // 4096 cells per triangle

  bool operator==(const EmissionCells&) const = default;
};

struct EmissionCellLimits {
  uint64_t max_cells = 1u << 20;    // 4 MB here, 12 MB more for sampling
  uint64_t max_lookups = 1u << 24;  // about 0.2 s on one core
};

// Needs scene.triangles, scene.emissive_triangles and scene.description's materials and
// textures (validated). Deterministic; runs on the calling thread's task arena.
EmissionCells build_emission_cells(const Scene& scene, const EmissionCellLimits& limits = {});

}  // namespace bakegi
