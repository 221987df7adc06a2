// The lattice of an Irradiance Vector Grid (Pacanowski et al. 2008, §3): an axis-aligned box
// cut into equal cells, one grid vertex at the centre of each cell. The paper puts vertices
// on the box's corners; at cell centres none lies on the walls of a room whose bounds are the
// box, where half of each sideways hemisphere would look behind the wall. Points in the outer
// half cell take the outermost vertices' values (interpolation clamps there).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace bakegi {

struct GridLayout {
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};
  std::array<uint32_t, 3> resolution{0, 0, 0};  // vertices (= cells) along x, y, z

  size_t vertex_count() const { return size_t(resolution[0]) * resolution[1] * resolution[2]; }
  glm::vec3 cell_size() const {
    return (bounds_max - bounds_min) /
           glm::vec3(float(resolution[0]), float(resolution[1]), float(resolution[2]));
  }
  size_t vertex_index(uint32_t i, uint32_t j, uint32_t k) const {
    return (size_t(k) * resolution[1] + j) * resolution[0] + i;
  }
  glm::vec3 vertex_position(uint32_t i, uint32_t j, uint32_t k) const {
    return bounds_min + (glm::vec3(float(i), float(j), float(k)) + 0.5f) * cell_size();
  }
  // The position of the vertex with index vertex_index(i, j, k).
  glm::vec3 vertex_position(size_t index) const {
    const size_t row = index / resolution[0];
    return vertex_position(uint32_t(index % resolution[0]), uint32_t(row % resolution[1]),
                           uint32_t(row / resolution[1]));
  }
  // Continuous vertex coordinates of a point: vertex (i, j, k) is at (i, j, k).
  glm::vec3 grid_coordinates(const glm::vec3& p) const {
    return (p - bounds_min) / cell_size() - 0.5f;
  }
};

// The smallest and largest vertex count per axis a grid may have: two vertices to interpolate
// between, and 1024 so that vertex indices fit every consumer (3D textures in WebGL2 allow
// 2048 at least; 1024^3 is far beyond any memory budget anyway).
inline constexpr uint32_t kMinGridResolution = 2;
inline constexpr uint32_t kMaxGridResolution = 1024;

// A layout over [bounds_min, bounds_max] with cells of about `cell_size` metres (0: the longest
// axis gets 32 cells, the paper's 32^3 grid), coarsened evenly until it has at most
// `max_vertices` vertices (the memory budget). Every axis gets at least two vertices; a flat
// axis (a single plane) is widened to one cell. Throws Error(INVALID_ARGUMENT) for
// non-finite or inverted bounds, a negative or non-finite cell size, or max_vertices < 8.
GridLayout choose_grid_layout(const glm::vec3& bounds_min, const glm::vec3& bounds_max,
                              float cell_size, uint64_t max_vertices);

// A layout with exactly `resolution` vertices per axis over the bounds (files, tests).
// Throws Error(INVALID_ARGUMENT) as above, or for a resolution outside
// [kMinGridResolution, kMaxGridResolution].
GridLayout make_grid_layout(const glm::vec3& bounds_min, const glm::vec3& bounds_max,
                            const std::array<uint32_t, 3>& resolution);

}  // namespace bakegi
