// Triangle meshes with known geometry for the mesh and web tests: a subdivided unit square
// and a closed unit UV sphere.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <glm/vec3.hpp>

namespace bakegi::test {

struct TestMesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
};

// An n x n grid of squares on the unit square at z = 0, two triangles each.
inline TestMesh plane(uint32_t n) {
  TestMesh mesh;
  for (uint32_t j = 0; j <= n; ++j) {
    for (uint32_t i = 0; i <= n; ++i) mesh.positions.push_back({float(i) / n, float(j) / n, 0});
  }
  for (uint32_t j = 0; j < n; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
    }
  }
  return mesh;
}

// A closed unit UV sphere: rings x segments quads (triangles at the poles).
inline TestMesh sphere(uint32_t rings, uint32_t segments) {
  TestMesh mesh;
  mesh.positions.push_back({0, 0, 1});
  for (uint32_t r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (uint32_t s = 0; s < segments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / segments;
      mesh.positions.push_back({float(std::sin(theta) * std::cos(phi)),
                                float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))});
    }
  }
  mesh.positions.push_back({0, 0, -1});
  const uint32_t south = uint32_t(mesh.positions.size() - 1);
  auto ring = [&](uint32_t r, uint32_t s) { return 1 + (r - 1) * segments + s % segments; };
  for (uint32_t s = 0; s < segments; ++s) {
    mesh.indices.insert(mesh.indices.end(), {0, ring(1, s), ring(1, s + 1)});
    mesh.indices.insert(mesh.indices.end(), {south, ring(rings - 1, s + 1), ring(rings - 1, s)});
    for (uint32_t r = 1; r + 1 < rings; ++r) {
      mesh.indices.insert(mesh.indices.end(), {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      mesh.indices.insert(mesh.indices.end(), {ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  }
  return mesh;
}

}  // namespace bakegi::test
