// The web page's visibility volume (grid/grid_visibility_volume.h): a wall thinner than a
// cell between a lit half of the grid and a dark half. The paper's reading leaks the lit
// vertices' light onto the dark side; the volume's reading does not, and agrees with the
// rays of Apply Grid (grid_visibility.h). And its file.
#include <gtest/gtest.h>

#include "grid/grid_interpolation.h"
#include "grid/grid_layout.h"
#include "grid/grid_visibility.h"
#include "grid/grid_visibility_volume.h"
#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "util/error.h"

namespace bakegi {
namespace {

constexpr float kLit = 0.8f;  // E / pi that the lit vertices give a receiver on any axis

// 2 x 1 x 1 m in 25 cm cells (vertices at x = 0.125 ... 1.875); a 10 cm wall at x = 1, the
// vertices left of it (x < 1) lit uniformly, those right of it dark.
struct WallScene {
  Scene scene;
  IrradianceVectorGrid grid;

  WallScene()
      : scene(build_scene(description())),
        grid(make_grid_layout(glm::vec3(0.0f), glm::vec3(2.0f, 1.0f, 1.0f), {8, 4, 4})) {
    for (size_t v = 0; v < grid.vertex_count(); ++v) {
      grid.valid[v] = 1;
      const bool lit = grid.layout.vertex_position(v).x < 1.0f;
      for (int h = 0; h < kGridHemispheres; ++h) {
        glm::mat3 m(0.0f);
        // Rows are colour channels: row . n is pi E for a normal along the hemisphere's axis.
        if (lit) m[0] = m[1] = m[2] = kPi * kLit * hemisphere_axis(h);
        grid.at(v, h) = m;
      }
    }
  }

  static SceneDescription description() {
    SceneDescription d;
    d.world_radiance = glm::vec3(0.1f);  // a scene needs light to be built; not read here
    const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
    d.meshes.push_back(test::make_cube(glm::vec3(0.95f, -0.1f, -0.1f), glm::vec3(1.05f, 1.1f, 1.1f),
                                       test::Facing::kOutward, grey));
    return d;
  }
};

TEST(GridVisibilityVolume, TheDarkSideOfAThinWallReadsNoLightThroughIt) {
  const WallScene s;
  const RayTracer tracer(s.scene);
  const GridVisibilityVolume volume =
      build_grid_visibility_volume(s.grid, s.scene, tracer, 2, false);
  EXPECT_EQ(volume.size, (std::array<uint32_t, 3>{16, 8, 8}));
  const glm::vec3 up(0.0f, 0.0f, 1.0f);
  // The floor 3 cm right of the wall: its reading's cell spans the wall.
  const glm::vec3 dark(1.08f, 0.5f, 0.0f);
  const glm::vec3 paper = evaluate_grid(s.grid, dark, up, GridInterpolation::kTrilinear);
  EXPECT_GT(paper.x, 0.1f * kLit);  // the leak the volume is for
  bool unsure = true;
  const glm::vec3 page = evaluate_grid_with_volume(s.grid, volume, dark, up,
                                                   GridDirectionalWeights::kSquared, &unsure);
  EXPECT_EQ(page, glm::vec3(0.0f));
  EXPECT_FALSE(unsure);  // it saw the dark vertices: a reading, not a guess
  // The wall's dark face itself, and the rays' reading there.
  const glm::vec3 face(1.05f, 0.5f, 0.5f), right(1.0f, 0.0f, 0.0f);
  EXPECT_EQ(
      evaluate_grid_with_volume(s.grid, volume, face, right, GridDirectionalWeights::kSquared),
      glm::vec3(0.0f));
  // The lit side, away from the wall and against its lit face: the lit value, all axes.
  for (const glm::vec3& n : {up, -right, glm::vec3(0.0f, 1.0f, 0.0f)}) {
    const glm::vec3 lit = evaluate_grid_with_volume(s.grid, volume, glm::vec3(0.5f, 0.5f, 0.0f), n,
                                                    GridDirectionalWeights::kSquared);
    EXPECT_NEAR(lit.x, kLit, 1e-5f);
  }
  const glm::vec3 against = evaluate_grid_with_volume(s.grid, volume, glm::vec3(0.95f, 0.5f, 0.5f),
                                                      -right, GridDirectionalWeights::kSquared);
  EXPECT_NEAR(against.y, kLit, 1e-5f);
  // Apply Grid's rays agree on the dark floor point.
  const glm::vec3 positions[1] = {dark}, normals[1] = {up};
  glm::vec3 rays[1];
  GridSceneLookup lookup;
  lookup.darken_buried = false;
  GridSceneStatistics statistics;
  evaluate_grid_in_scene(s.grid, s.scene, tracer, positions, normals, lookup, rays, {}, statistics);
  EXPECT_EQ(rays[0], glm::vec3(0.0f));
}

// Vertices inside the wall (invalid: the grid's gather found them in a solid) are never read.
TEST(GridVisibilityVolume, InvalidVerticesAreNotRead) {
  WallScene s;
  const RayTracer tracer(s.scene);
  for (size_t v = 0; v < s.grid.vertex_count(); ++v) s.grid.valid[v] = 0;
  const GridVisibilityVolume volume =
      build_grid_visibility_volume(s.grid, s.scene, tracer, 2, false);
  for (size_t i = 0; i < volume.subvoxel_count(); ++i) {
    ASSERT_EQ(volume.codes[2 * i], 0) << i;
    ASSERT_EQ(volume.codes[2 * i + 1], kNoFallback) << i;
  }
  bool unsure = false;
  EXPECT_EQ(
      evaluate_grid_with_volume(s.grid, volume, glm::vec3(0.5f, 0.5f, 0.0f), glm::vec3(0, 0, 1),
                                GridDirectionalWeights::kSquared, &unsure),
      glm::vec3(0.0f));
  EXPECT_TRUE(unsure);
}

// A surface facing out of the grid's box (a block's top above it): its points read from one
// subvoxel out, clamped back into the block, where no point is open to judge from. Out there
// is only the world: under a sky the surface reads the paper's reading, under a black world
// nothing (and is unsure).
TEST(GridVisibilityVolume, ASurfaceFacingOutOfTheGridReadsWhatTheWorldGives) {
  WallScene s;
  SceneDescription d;
  d.world_radiance = glm::vec3(0.1f);
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  d.meshes.push_back(test::make_cube(glm::vec3(-0.1f, -0.1f, 0.5f), glm::vec3(2.1f, 1.1f, 1.2f),
                                     test::Facing::kOutward, grey));
  const Scene block = build_scene(d);
  for (size_t v = 0; v < s.grid.vertex_count(); ++v) {
    s.grid.valid[v] = s.grid.layout.vertex_position(v).z < 0.5f;  // as the gather finds them
  }
  const RayTracer tracer(block);
  const glm::vec3 top(0.5f, 0.5f, 1.2f), up(0.0f, 0.0f, 1.0f);
  const GridVisibilityVolume sky = build_grid_visibility_volume(s.grid, block, tracer, 2, true);
  EXPECT_NEAR(evaluate_grid_with_volume(s.grid, sky, top, up, GridDirectionalWeights::kSquared).x,
              kLit, 1e-5f);
  const GridVisibilityVolume black = build_grid_visibility_volume(s.grid, block, tracer, 2, false);
  bool unsure = false;
  EXPECT_EQ(
      evaluate_grid_with_volume(s.grid, black, top, up, GridDirectionalWeights::kSquared, &unsure),
      glm::vec3(0.0f));
  EXPECT_TRUE(unsure);
}

// 8 subvoxels a cell up to 16 cells, then about 1/64 of the grid's longest side, even.
TEST(GridVisibilityVolume, TheWebExportsSubdivisionFollowsTheGridsCells) {
  const auto subdivision = [](uint32_t cells) {
    return page_visibility_subdivision(
        make_grid_layout(glm::vec3(0.0f), glm::vec3(1.0f), {cells, cells / 2 + 2, 2}));
  };
  EXPECT_EQ(subdivision(64), 2u);
  EXPECT_EQ(subdivision(32), 2u);
  EXPECT_EQ(subdivision(24), 4u);
  EXPECT_EQ(subdivision(17), 4u);
  EXPECT_EQ(subdivision(16), 8u);
  EXPECT_EQ(subdivision(12), 8u);
  EXPECT_EQ(subdivision(8), 8u);
  EXPECT_EQ(subdivision(4), 8u);
}

// A volume past its subvoxel budget is refused before anything is allocated for it.
TEST(GridVisibilityVolume, TooManySubvoxelsAreRefused) {
  const WallScene s;
  const RayTracer tracer(s.scene);
  const IrradianceVectorGrid large(
      make_grid_layout(glm::vec3(0.0f), glm::vec3(2.0f, 1.0f, 1.0f), {33, 33, 33}));
  ASSERT_GT(large.vertex_count() * 8 * 8 * 8, kMaxVisibilitySubvoxels);
  try {
    build_grid_visibility_volume(large, s.scene, tracer, 8, false);
    ADD_FAILURE() << "built";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY);
  }
}

TEST(GridVisibilityVolume, FileRoundTripsAndRefusesDamage) {
  const WallScene s;
  const RayTracer tracer(s.scene);
  EXPECT_THROW(build_grid_visibility_volume(s.grid, s.scene, tracer, 3, false), Error);
  const GridVisibilityVolume volume =
      build_grid_visibility_volume(s.grid, s.scene, tracer, 4, false);
  const std::vector<uint8_t> bytes = encode_visibility_file(volume, s.grid.layout);
  EXPECT_LT(bytes.size(), volume.codes.size() / 4);  // mostly "all seen": it deflates well
  const GridVisibilityVolume read = decode_visibility_file(bytes, s.grid.layout);
  EXPECT_EQ(read.subdivision, 4u);
  EXPECT_EQ(read.size, volume.size);
  EXPECT_EQ(read.codes, volume.codes);
  auto refused = [&](std::vector<uint8_t> damaged, const GridLayout& layout) {
    try {
      decode_visibility_file(damaged, layout);
    } catch (const Error& e) {
      return e.status() == BAKEGI_ERROR_BAD_FILE;
    }
    return false;
  };
  std::vector<uint8_t> damaged = bytes;
  damaged[0] = 'X';
  EXPECT_TRUE(refused(damaged, s.grid.layout));
  EXPECT_TRUE(refused(std::vector<uint8_t>(bytes.begin(), bytes.end() - 5), s.grid.layout));
  EXPECT_TRUE(refused(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 20), s.grid.layout));
  const GridLayout other =
      make_grid_layout(glm::vec3(0.0f), glm::vec3(2.0f, 1.0f, 1.0f), {8, 4, 5});
  EXPECT_TRUE(refused(bytes, other));
}

}  // namespace
}  // namespace bakegi
