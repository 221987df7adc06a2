// Which exported corners read the grid at all (web/corner_grid_reach.h), and how the glTF
// carries it: a floor with a block sunk into it. The floor's corners under the block read
// nothing (buried), those in the open read the grid, and a floor vertex on the block's edge,
// buried for its triangles under the block and open for the others, becomes two glTF vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "grid/grid_layout.h"
#include "grid/irradiance_vector_grid.h"
#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "web/corner_grid_reach.h"
#include "web/gltf_export.h"

namespace bakegi {
namespace {

constexpr int kTiles = 8;  // the floor: 2 x 1 m in 8 x 4 tiles of 25 cm, one mesh
const glm::vec3 kBlockLo(0.75f, 0.25f, -0.05f), kBlockHi(1.25f, 0.75f, 0.5f);

SceneDescription floor_and_block() {
  SceneDescription d;
  d.world_radiance = glm::vec3(0.1f);
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  Mesh floor;
  for (int j = 0; j <= kTiles / 2; ++j) {
    for (int i = 0; i <= kTiles; ++i) floor.positions.push_back({0.25f * i, 0.25f * j, 0.0f});
  }
  for (int j = 0; j < kTiles / 2; ++j) {
    for (int i = 0; i < kTiles; ++i) {
      const uint32_t a = uint32_t(j * (kTiles + 1) + i), b = a + 1, c = a + kTiles + 2,
                     e = a + kTiles + 1;
      floor.indices.insert(floor.indices.end(), {a, b, c, a, c, e});  // facing +z
    }
  }
  floor.material = grey;
  d.meshes.push_back(std::move(floor));
  d.meshes.push_back(test::make_cube(kBlockLo, kBlockHi, test::Facing::kOutward, grey));
  return d;
}

// A grid over the floor and the block, its vertices inside the block invalid (as the gather
// finds them); the light it holds is not read here.
IrradianceVectorGrid grid_over() {
  IrradianceVectorGrid grid(
      make_grid_layout(glm::vec3(0.0f, 0.0f, -0.1f), glm::vec3(2.0f, 1.0f, 0.9f), {8, 4, 4}));
  for (size_t v = 0; v < grid.vertex_count(); ++v) {
    const glm::vec3 p = grid.layout.vertex_position(v);
    grid.valid[v] =
        !(glm::all(glm::greaterThan(p, kBlockLo)) && glm::all(glm::lessThan(p, kBlockHi)));
  }
  return grid;
}

bool under_block(const glm::vec3& p) {
  return p.x > kBlockLo.x && p.x < kBlockHi.x && p.y > kBlockLo.y && p.y < kBlockHi.y;
}

TEST(CornerGridReach, CornersUnderABlockReadNothingAndTheOpenFloorReads) {
  const Scene scene = build_scene(floor_and_block());
  const RayTracer tracer(scene);
  const IrradianceVectorGrid grid = grid_over();
  const std::vector<std::vector<uint8_t>> reads = corners_reading_grid(grid, scene, tracer);
  ASSERT_EQ(reads.size(), 2u);
  const Mesh& floor = scene.description.meshes[0];
  ASSERT_EQ(reads[0].size(), floor.indices.size());
  int buried = 0, open = 0;
  for (size_t t = 0; t < floor.indices.size() / 3; ++t) {
    glm::vec3 centre(0.0f);
    for (int c = 0; c < 3; ++c) centre += floor.positions[floor.indices[3 * t + c]] / 3.0f;
    for (int c = 0; c < 3; ++c) {
      // A corner is judged a little inside its triangle: by where the triangle lies.
      const uint8_t expected = under_block(centre) ? 0 : 1;
      EXPECT_EQ(reads[0][3 * t + c], expected) << "triangle " << t << " corner " << c;
      (expected ? open : buried) += 1;
    }
  }
  EXPECT_EQ(buried, 4 * 2 * 3);  // the 4 tiles under the block
  EXPECT_GT(open, buried);
  // The block's own faces above the floor read; the parts of its sides below the floor lie
  // under it and do not.
  for (const uint8_t r : reads[1]) EXPECT_TRUE(r == 0 || r == 1);
}

TEST(CornerGridReach, TheGltfKeepsCornersThatDifferApartAndCarriesTheAttribute) {
  const Scene scene = build_scene(floor_and_block());
  const RayTracer tracer(scene);
  const IrradianceVectorGrid grid = grid_over();
  WebExportOptions options;
  const WebGltf without = encode_web_gltf(scene.description, options);
  EXPECT_EQ(without.json.find("_BAKEGI_READS_GRID"), std::string::npos);
  options.corner_reads_grid = corners_reading_grid(grid, scene, tracer);
  const WebGltf with = encode_web_gltf(scene.description, options);
  EXPECT_NE(with.json.find("\"_BAKEGI_READS_GRID\":"), std::string::npos);
  // With the block's corners all reading, only the floor changes: the 8 vertices on the
  // block's outline serve buried and open triangles and are kept twice; the one inside it
  // serves buried triangles only.
  std::fill(options.corner_reads_grid[1].begin(), options.corner_reads_grid[1].end(), 1);
  const WebGltf split = encode_web_gltf(scene.description, options);
  EXPECT_EQ(split.vertices, without.vertices + 8);
  EXPECT_EQ(split.faces, without.faces);
  // Mismatched sizes are ignored, not read past.
  options.corner_reads_grid[0].pop_back();
  EXPECT_NO_THROW(encode_web_gltf(scene.description, options));
}

}  // namespace
}  // namespace bakegi
