// Reading the grid where the scene is known: the paper's interpolation (§3.2) blends the grid
// vertices around a point whatever lies between them, so light leaks through walls thinner
// than a cell (measured: 47% NRMSE in the suite's two rooms, whose dark room reads the lit
// room's vertices; docs/ivg.md) and buried faces (a floor under a box) read the open side's
// light. Here a point reads only the vertices it sees: a shadow ray from the point (lifted
// off its surface along its normal) to each vertex of its interpolation, the vertex dropped
// when the ray is blocked or the vertex lies inside geometry (the grid's invalid vertices),
// the others sharing its weight, as irradiance probes in games are read (e.g. DDGI's
// visibility test, here exact with rays instead of a depth map); vertices more than half a
// cell behind the point's own surface are the other side's and dropped without a ray. A
// point that sees none of its vertices reads the ones a cell further out that it sees (4^3
// around it, by inverse squared distance); seeing none of those either (a face on the
// outside of the rooms, a closed nook) it reads 0 and is reported unsure. Buried points
// (their rays meet back faces: lightmap/backface_rejection.h) read 0, as a bake sees them.
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "grid/grid_interpolation.h"
#include "grid/irradiance_vector_grid.h"
#include "lightmap/backface_rejection.h"

namespace bakegi {

class JobContext;
class RayTracer;
struct Scene;

struct GridSceneLookup {
  GridInterpolation interpolation = GridInterpolation::kTrilinear;
  GridDirectionalWeights weights = GridDirectionalWeights::kSquared;
  bool visibility = true;     // read only the vertices a point sees
  bool darken_buried = true;  // points inside or under geometry read 0
  BackfaceRejectionOptions buried;
};

struct GridSceneStatistics {
  uint64_t rays = 0;
  uint64_t buried = 0;  // points set to 0
  uint64_t unsure = 0;  // points that saw none of their vertices
};

// What became of a point (bakegi.h's bakegi_grid_evaluate_in_scene).
inline constexpr uint8_t kGridPointRead = 0;
inline constexpr uint8_t kGridPointUnsure = 1;  // saw no vertex near it: 0
inline constexpr uint8_t kGridPointBuried = 2;  // inside or under geometry: 0

// out and unsure (empty, or one kGridPoint* code per point) have one entry per point.
// Parallel.
void evaluate_grid_in_scene(const IrradianceVectorGrid& grid, const Scene& scene,
                            const RayTracer& tracer, std::span<const glm::vec3> positions,
                            std::span<const glm::vec3> normals, const GridSceneLookup& lookup,
                            std::span<glm::vec3> out, std::span<uint8_t> unsure,
                            GridSceneStatistics& statistics);

}  // namespace bakegi
