// Mesh topology (scene/mesh_topology.h): welding split corners by position, then boundary,
// non-manifold and inconsistently wound edges; build_scene records it per mesh.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "light_transport_fixtures.h"
#include "scene/mesh_topology.h"
#include "scene/scene_validation.h"

namespace bakegi::test {
namespace {

MeshTopology topology_of(const Mesh& mesh) {
  return analyze_mesh_topology(mesh.positions, mesh.indices);
}

// Every triangle with its own three corners, as flat-shaded exports split them; copy i moves
// by up to `jitter` (a different amount each: float noise of an exporter's transform).
Mesh split_corners(const Mesh& mesh, float jitter) {
  Mesh split = mesh;
  split.positions.clear();
  split.indices.clear();
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    const float step = jitter * float(i + 1) / float(mesh.indices.size());
    split.positions.push_back(mesh.positions[mesh.indices[i]] +
                              glm::vec3(step, 0.5f * step, -step));
    split.indices.push_back(uint32_t(i));
  }
  return split;
}

TEST(MeshTopology, ClosedCubeIsAManifoldSolid) {
  const Mesh cube = make_cube({0, 0, 0}, {1, 1, 1}, Facing::kOutward, 0);
  const MeshTopology t = topology_of(cube);
  EXPECT_EQ(t.welded_vertices, 8u);
  EXPECT_EQ(t.edges, 18u);  // 12 cube edges + 6 face diagonals
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_FALSE(t.open());
  EXPECT_EQ(describe_topology_problems(t), "");
}

TEST(MeshTopology, SplitCornersAreWelded) {
  const Mesh cube = make_cube({-2, 3, 1}, {-1, 5, 1.5f}, Facing::kInward, 0);
  // 36 separate corners: exact copies, and copies up to 2e-6 apart (the mesh's diagonal is
  // 2.29 m: below the 1e-5 relative weld tolerance, 2.3e-5 m) still make a closed cube.
  for (const float jitter : {0.0f, 2e-6f}) {
    SCOPED_TRACE(jitter);
    const MeshTopology t = topology_of(split_corners(cube, jitter));
    EXPECT_EQ(t.welded_vertices, 8u);
    EXPECT_FALSE(t.open());
    EXPECT_EQ(t.inconsistent_edges, 0u);
  }
  // Copies at least 2e-3 / 36 = 5.6e-5 m apart, above the tolerance, are different vertices:
  // every edge is a boundary.
  const MeshTopology apart = topology_of(split_corners(cube, 2e-3f));
  EXPECT_TRUE(apart.open());
  EXPECT_EQ(apart.welded_vertices, 36u);
}

TEST(MeshTopology, PlanesAndHolesAreOpen) {
  SceneDescription d;
  add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1, 0);
  const MeshTopology quad = topology_of(d.meshes[0]);
  EXPECT_EQ(quad.boundary_edges, 4u);
  EXPECT_EQ(quad.edges, 5u);
  EXPECT_TRUE(quad.open());
  EXPECT_EQ(describe_topology_problems(quad), "4 open edges");

  Mesh box = make_cube({0, 0, 0}, {1, 1, 1}, Facing::kOutward, 0);
  box.indices.resize(box.indices.size() - 6);  // the last face (x = hi) left out
  const MeshTopology open_box = topology_of(box);
  EXPECT_EQ(open_box.boundary_edges, 4u);
  EXPECT_EQ(open_box.non_manifold_edges, 0u);
  EXPECT_TRUE(open_box.open());
}

TEST(MeshTopology, FinsAndFlippedFaces) {
  // Three triangles on one edge (a fin): that edge is non-manifold, the other six boundary.
  Mesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0.5f, 0, 1}};
  fin.indices = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const MeshTopology f = topology_of(fin);
  EXPECT_EQ(f.non_manifold_edges, 1u);
  EXPECT_EQ(f.boundary_edges, 6u);
  EXPECT_TRUE(f.open());

  // A cube with one triangle wound the other way: still closed, but its three edges are each
  // used twice in the same direction.
  Mesh cube = make_cube({0, 0, 0}, {1, 1, 1}, Facing::kOutward, 0);
  std::swap(cube.indices[1], cube.indices[2]);
  const MeshTopology flipped = topology_of(cube);
  EXPECT_FALSE(flipped.open());
  EXPECT_EQ(flipped.inconsistent_edges, 3u);
  EXPECT_EQ(describe_topology_problems(flipped), "3 edges between faces of opposite winding");
}

TEST(MeshTopology, DegenerateInputs) {
  EXPECT_EQ(analyze_mesh_topology({}, {}), MeshTopology{});
  // Welding collapses a triangle whose corners coincide: it has no edges.
  const std::vector<glm::vec3> same = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  const std::vector<uint32_t> indices = {0, 1, 2};
  const MeshTopology t = analyze_mesh_topology(same, indices);
  EXPECT_EQ(t.welded_vertices, 1u);
  EXPECT_EQ(t.edges, 0u);
  EXPECT_FALSE(t.open());
}

TEST(MeshTopology, BuildSceneRecordsItPerMesh) {
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.5f));
  d.meshes.push_back(make_cube({-1, -1, 0}, {1, 1, 2}, Facing::kInward, white));
  add_quad(d, {0, 0, 1}, {0, 1, 0}, {0, 0, 1}, 1, 1, white);
  d.lights.push_back(point_light({0.5f, 0, 1}, glm::vec3(1.0f)));
  const Scene scene = build_scene(d);
  ASSERT_EQ(scene.mesh_topology.size(), 2u);
  EXPECT_FALSE(scene.mesh_topology[0].open());
  EXPECT_TRUE(scene.mesh_topology[1].open());
}

}  // namespace
}  // namespace bakegi::test
