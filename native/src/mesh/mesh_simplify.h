// Levels of detail of a triangle mesh with meshoptimizer's simplifier (Debian's
// libmeshoptimizer): what the grid lighting is measured on per level of detail (issue 16,
// item 4) and what the streamed progressive mesh is made of (§4.2, mesh/progressive_mesh.h).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace bakegi {

struct SimplifiedTriangles {
  std::vector<uint32_t> indices;  // three per triangle, into the input's vertices
  float relative_error = 0.0f;    // the simplifier's deviation over the mesh's extent
};

// `indices` (three per triangle, into `positions`) simplified by edge collapses towards
// target_ratio (0, 1] of its triangles, keeping the surface within max_relative_error of the
// mesh's extent (1 = let the triangle count decide). The simplifier keeps the topology, so
// it may stop above the target (a mesh with many borders). Throws Error on bad input.
SimplifiedTriangles simplify_triangles(std::span<const glm::vec3> positions,
                                       std::span<const uint32_t> indices, double target_ratio,
                                       float max_relative_error);

}  // namespace bakegi
