#include "web/corner_grid_reach.h"

#include <cmath>

#include "grid/grid_visibility.h"
#include "scene/ray_tracer.h"

namespace bakegi {

namespace {

// As the add-on's bake points (export/points.py, INWARD_FRACTION): a corner is asked about
// this fraction of the way towards its face's centre, so that one on a concave junction (a
// floor's corner at the foot of a wall) is not judged by float rounding in the neighbouring
// surface's plane (where its rays meet that surface's back: buried).
constexpr float kInwardFraction = 2e-3f;

}  // namespace

std::vector<std::vector<uint8_t>> corners_reading_grid(const IrradianceVectorGrid& grid,
                                                       const Scene& built,
                                                       const RayTracer& tracer) {
  const auto& meshes = built.description.meshes;
  // Every corner as a point; the degenerate ones are left out and read.
  std::vector<glm::vec3> positions, normals;
  std::vector<std::pair<uint32_t, size_t>> corner_of;  // (mesh, corner) per point
  std::vector<std::vector<uint8_t>> reads(meshes.size());
  for (uint32_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    reads[m].assign(mesh.indices.size(), 1);
    for (size_t t = 0; t < mesh.indices.size() / 3; ++t) {
      glm::vec3 p[3];
      bool in_range = true;
      for (int c = 0; c < 3; ++c) {
        const uint32_t v = mesh.indices[3 * t + c];
        in_range = in_range && v < mesh.positions.size();
        if (in_range) p[c] = mesh.positions[v];
      }
      if (!in_range) continue;
      const glm::vec3 face = glm::cross(p[1] - p[0], p[2] - p[0]);
      for (int c = 0; c < 3; ++c) {
        const glm::vec3 n = mesh.corner_normals.empty() ? face : mesh.corner_normals[3 * t + c];
        const float length = glm::length(n);
        if (!(length > 0.0f) || !std::isfinite(length)) continue;
        const glm::vec3 centre = (p[0] + p[1] + p[2]) / 3.0f;
        positions.push_back(p[c] + kInwardFraction * (centre - p[c]));
        normals.push_back(n / length);
        corner_of.push_back({m, 3 * t + c});
      }
    }
  }
  std::vector<glm::vec3> values(positions.size());
  std::vector<uint8_t> codes(positions.size(), kGridPointRead);
  GridSceneStatistics statistics;
  evaluate_grid_in_scene(grid, built, tracer, positions, normals, GridSceneLookup{}, values, codes,
                         statistics);
  for (size_t i = 0; i < codes.size(); ++i) {
    if (codes[i] != kGridPointRead) reads[corner_of[i].first][corner_of[i].second] = 0;
  }
  return reads;
}

}  // namespace bakegi
