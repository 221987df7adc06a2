// Levels of detail (mesh/mesh_simplify.h, bakegi_mesh_simplify): a plane keeps its area and
// shape at any ratio, a sphere reaches the ratio within a deviation that grows as it
// coarsens, and bad input is refused through the C API with a message.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "bakegi/bakegi.h"
#include "mesh/mesh_simplify.h"
#include "test_meshes.h"

namespace bakegi {
namespace {

using test::plane;
using test::sphere;
using test::TestMesh;

double area(const std::vector<glm::vec3>& p, const std::vector<uint32_t>& indices) {
  double total = 0.0;
  for (size_t t = 0; t < indices.size(); t += 3) {
    const glm::vec3 e1 = p[indices[t + 1]] - p[indices[t]];
    const glm::vec3 e2 = p[indices[t + 2]] - p[indices[t]];
    total += 0.5 * std::sqrt(double(std::pow(e1.y * e2.z - e1.z * e2.y, 2) +
                                    std::pow(e1.z * e2.x - e1.x * e2.z, 2) +
                                    std::pow(e1.x * e2.y - e1.y * e2.x, 2)));
  }
  return total;
}

TEST(MeshSimplify, APlaneKeepsItsAreaAtATenthOfItsTriangles) {
  const TestMesh mesh = plane(20);  // 800 triangles
  const SimplifiedTriangles lod = simplify_triangles(mesh.positions, mesh.indices, 0.1, 1.0f);
  ASSERT_EQ(lod.indices.size() % 3, 0u);
  EXPECT_LE(lod.indices.size() / 3, 80u);
  EXPECT_GE(lod.indices.size() / 3, 2u);
  // Collapses on a plane move nothing off it: the area stays 1 (float sums: 1e-4).
  EXPECT_NEAR(area(mesh.positions, lod.indices), 1.0, 1e-4);
  EXPECT_LT(lod.relative_error, 1e-4f);
}

TEST(MeshSimplify, ASphereCoarsensWithGrowingDeviation) {
  const TestMesh mesh = sphere(32, 64);  // 3,968 triangles
  const double full_area = area(mesh.positions, mesh.indices);
  float previous_error = -1.0f;
  for (const double ratio : {0.5, 0.1, 0.01}) {
    const SimplifiedTriangles lod = simplify_triangles(mesh.positions, mesh.indices, ratio, 1.0f);
    const double triangles = double(lod.indices.size() / 3);
    // A closed sphere has no borders to hold collapses back: the ratio is reached.
    EXPECT_LE(triangles, std::ceil(ratio * double(mesh.indices.size() / 3)) + 1.0) << ratio;
    EXPECT_GT(triangles, 0.0);
    EXPECT_GE(lod.relative_error, previous_error) << ratio;
    previous_error = lod.relative_error;
    // Inscribed polyhedra lose area as they coarsen, but stay a sphere (40 triangles still
    // hold well over half of 4 pi).
    EXPECT_LE(area(mesh.positions, lod.indices), full_area * 1.001) << ratio;
    EXPECT_GT(area(mesh.positions, lod.indices), 0.5 * full_area) << ratio;
  }
  EXPECT_GT(previous_error, 0.0f);
  EXPECT_LT(previous_error, 0.5f);
}

TEST(MeshSimplify, AnErrorBoundStopsTheCollapses) {
  const TestMesh mesh = sphere(32, 64);
  const SimplifiedTriangles bounded =
      simplify_triangles(mesh.positions, mesh.indices, 0.01, 0.001f);
  const SimplifiedTriangles free = simplify_triangles(mesh.positions, mesh.indices, 0.01, 1.0f);
  EXPECT_LE(bounded.relative_error, 0.001f);
  EXPECT_GT(bounded.indices.size(), 2 * free.indices.size());
}

TEST(MeshSimplify, TheCApiRefusesBadInput) {
  const TestMesh mesh = plane(4);
  const float* xyz = &mesh.positions[0].x;
  std::vector<uint32_t> out(mesh.indices.size());
  uint64_t written = 0;
  float error = -1.0f;
  ASSERT_EQ(bakegi_mesh_simplify(xyz, mesh.positions.size(), mesh.indices.data(),
                                 mesh.indices.size(), 0.5f, 1.0f, out.data(), &written, &error),
            BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_LE(written, mesh.indices.size() / 2 + 3);
  EXPECT_GE(error, 0.0f);

  std::vector<uint32_t> bad = mesh.indices;
  bad[4] = uint32_t(mesh.positions.size());
  EXPECT_EQ(bakegi_mesh_simplify(xyz, mesh.positions.size(), bad.data(), bad.size(), 0.5f, 1.0f,
                                 out.data(), &written, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("past the"), std::string::npos);
  EXPECT_EQ(bakegi_mesh_simplify(xyz, mesh.positions.size(), mesh.indices.data(),
                                 mesh.indices.size(), 0.0f, 1.0f, out.data(), &written, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_mesh_simplify(xyz, mesh.positions.size(), mesh.indices.data(), 7, 0.5f, 1.0f,
                                 out.data(), &written, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_mesh_simplify(nullptr, mesh.positions.size(), mesh.indices.data(),
                                 mesh.indices.size(), 0.5f, 1.0f, out.data(), &written, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
}

}  // namespace
}  // namespace bakegi
