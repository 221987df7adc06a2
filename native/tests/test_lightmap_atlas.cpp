// Several objects in one lightmap atlas (bakegi_lightmaps_add_to): two quads whose UVs lie
// in the left and right halves of one 16 x 8 map give exactly the samples, coverage and
// resolved texels of the same quads rasterized alone into two 8 x 8 maps, and misuse (a
// lightmap or mesh that does not exist, adding after rejection) is refused with a message.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lightmap/texel_rasterizer.h"
#include "bakegi/bakegi.h"
#include "lightmap_test_scene.h"
#include "util/error.h"
#include "lightmap/exr_writer.h"

namespace bakegi::test {
namespace {

using LightmapAtlas = LightmapFilesTest;

// A fake bake result that differs per point: its position, so that texels differ too and
// any mix-up of samples between objects or texels shows in the images.
std::vector<float> position_values(const bakegi_points* points) {
  const uint64_t count = bakegi_points_count(points);
  std::vector<float> positions(3 * count);
  EXPECT_EQ(bakegi_points_get(points, positions.data(), nullptr, nullptr), BAKEGI_OK);
  for (float& v : positions) v += 10.0f;  // positive, like light
  return positions;
}

PointsHandle points_of(const bakegi_lightmaps* lightmaps) {
  bakegi_points* raw = nullptr;
  EXPECT_EQ(bakegi_lightmaps_get_points(lightmaps, &raw), BAKEGI_OK) << bakegi_last_error();
  return PointsHandle(raw);
}

TEST_F(LightmapAtlas, TwoMeshesInOneAtlasMatchTwoSeparateMaps) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const Quad wall({0, 2, 1}, {2, 0, 0}, {0, 0, 1});
  const uint32_t floor_mesh = floor.add_to(scene.get(), 10);
  const uint32_t wall_mesh = wall.add_to(scene.get(), 11);

  // Separately: each quad alone in an 8 x 8 map.
  LightmapsPtr separate = new_lightmaps();
  ASSERT_EQ(bakegi_lightmaps_add(separate.get(), scene.get(), floor_mesh, floor.uvs.data(), 8, 8,
                                 nullptr),
            BAKEGI_OK);
  ASSERT_EQ(
      bakegi_lightmaps_add(separate.get(), scene.get(), wall_mesh, wall.uvs.data(), 8, 8, nullptr),
      BAKEGI_OK);

  // One 16 x 8 atlas: the floor in the left half, then the wall added into the right half.
  // Halving u and adding 0.5 is exact in float, so the texel grids coincide exactly.
  const std::vector<float> floor_uvs = floor.placed_uvs({0.5f, 1.0f}, {0.0f, 0.0f});
  const std::vector<float> wall_uvs = wall.placed_uvs({0.5f, 1.0f}, {0.5f, 0.0f});
  LightmapsPtr atlas = new_lightmaps();
  uint32_t index = 99;
  ASSERT_EQ(
      bakegi_lightmaps_add(atlas.get(), scene.get(), floor_mesh, floor_uvs.data(), 16, 8, &index),
      BAKEGI_OK);
  ASSERT_EQ(index, 0u);
  ASSERT_EQ(bakegi_lightmaps_add_to(atlas.get(), 0, scene.get(), wall_mesh, wall_uvs.data()),
            BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_EQ(bakegi_lightmaps_count(atlas.get()), 1u);

  bakegi_lightmap_info a{}, s0{}, s1{};
  ASSERT_EQ(bakegi_lightmaps_get_info(atlas.get(), 0, &a), BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_get_info(separate.get(), 0, &s0), BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_get_info(separate.get(), 1, &s1), BAKEGI_OK);
  EXPECT_EQ(a.width, 16u);
  EXPECT_EQ(a.height, 8u);
  EXPECT_EQ(a.point_count, s0.point_count + s1.point_count);
  EXPECT_EQ(a.covered_texels, s0.covered_texels + s1.covered_texels);
  EXPECT_EQ(a.covered_texels, 128u);  // both halves wholly covered
  EXPECT_EQ(a.skipped_triangles, 0u);

  // The same points in the same order (floor's, then wall's), with their object ids.
  PointsHandle atlas_points = points_of(atlas.get());
  PointsHandle separate_points = points_of(separate.get());
  const uint64_t count = bakegi_points_count(atlas_points.get());
  ASSERT_EQ(count, bakegi_points_count(separate_points.get()));
  std::vector<float> pa(3 * count), ps(3 * count), na(3 * count), ns(3 * count);
  std::vector<uint32_t> ia(count), is(count);
  ASSERT_EQ(bakegi_points_get(atlas_points.get(), pa.data(), na.data(), ia.data()), BAKEGI_OK);
  ASSERT_EQ(bakegi_points_get(separate_points.get(), ps.data(), ns.data(), is.data()), BAKEGI_OK);
  EXPECT_EQ(pa, ps);
  EXPECT_EQ(na, ns);
  EXPECT_EQ(ia, is);
  EXPECT_EQ(ia.front(), 10u);
  EXPECT_EQ(ia.back(), 11u);

  // Resolved texels (full float, no padding, so nothing bleeds between the halves): the
  // atlas' halves are the two separate maps, texel for texel.
  const std::vector<float> rgb = position_values(atlas_points.get());
  ASSERT_EQ(bakegi_lightmaps_write_exr(atlas.get(), 0, rgb.data(), count, path("atlas.exr").c_str(),
                                       0, 1, BAKEGI_EXR_ZIP),
            BAKEGI_OK)
      << bakegi_last_error();
  for (uint32_t m = 0; m < 2; ++m) {
    const std::string name = path("separate" + std::to_string(m) + ".exr");
    ASSERT_EQ(bakegi_lightmaps_write_exr(separate.get(), m, rgb.data(), count, name.c_str(), 0, 1,
                                         BAKEGI_EXR_ZIP),
              BAKEGI_OK)
        << bakegi_last_error();
  }
  const RgbImage atlas_image = read_exr(path("atlas.exr"));
  const RgbImage left = read_exr(path("separate0.exr")), right = read_exr(path("separate1.exr"));
  ASSERT_EQ(atlas_image.pixels.size(), 128u);
  for (uint32_t y = 0; y < 8; ++y) {
    for (uint32_t x = 0; x < 16; ++x) {
      const glm::vec3 expected = x < 8 ? left.pixels[y * 8 + x] : right.pixels[y * 8 + (x - 8)];
      EXPECT_EQ(atlas_image.pixels[y * 16 + x], expected) << x << "," << y;
      EXPECT_GT(expected.x, 0.0f);  // every texel baked
    }
  }
}

TEST_F(LightmapAtlas, MisuseIsRefusedWithAMessage) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 0);
  const std::vector<float> half = floor.placed_uvs({0.5f, 1.0f}, {0.0f, 0.0f});
  LightmapsPtr lightmaps = new_lightmaps();
  bakegi_lightmaps* l = lightmaps.get();

  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), mesh, half.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("lightmap 0 does not exist"), std::string::npos)
      << bakegi_last_error();
  ASSERT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, half.data(), 8, 8, nullptr), BAKEGI_OK);
  bakegi_lightmap_info before{};
  ASSERT_EQ(bakegi_lightmaps_get_info(l, 0, &before), BAKEGI_OK);

  EXPECT_EQ(bakegi_lightmaps_add_to(l, 1, scene.get(), mesh, half.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("lightmap 1"), std::string::npos);
  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), 7, half.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("mesh 7"), std::string::npos);
  EXPECT_EQ(bakegi_lightmaps_add_to(nullptr, 0, scene.get(), mesh, half.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, nullptr, mesh, half.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), mesh, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("lightmap_uvs is NULL"), std::string::npos);
  std::vector<float> nan_uvs = half;
  nan_uvs[5] = NAN;
  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), mesh, nan_uvs.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);

  // A rejection refused for its options changed nothing, so adding is still allowed.
  ASSERT_EQ(bakegi_lightmaps_reject_inside(l, scene.get(), 0, 2.0f, 0, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  const std::vector<float> upper = floor.placed_uvs({0.5f, 0.25f}, {0.5f, 0.75f});
  ASSERT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), mesh, upper.data()), BAKEGI_OK)
      << bakegi_last_error();
  ASSERT_EQ(bakegi_lightmaps_get_info(l, 0, &before), BAKEGI_OK);

  uint64_t rejected = 0;
  ASSERT_EQ(bakegi_lightmaps_reject_inside(l, scene.get(), 0, 0, 0, &rejected), BAKEGI_OK)
      << bakegi_last_error();
  const std::vector<float> right = floor.placed_uvs({0.5f, 1.0f}, {0.5f, 0.0f});
  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), mesh, right.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("reject_inside"), std::string::npos)
      << bakegi_last_error();

  // Failed calls added nothing.
  bakegi_lightmap_info after{};
  ASSERT_EQ(bakegi_lightmaps_get_info(l, 0, &after), BAKEGI_OK);
  EXPECT_EQ(after.point_count + after.rejected_samples, before.point_count);
  EXPECT_EQ(bakegi_lightmaps_count(l), 1u);
}

// The merge itself: samples concatenated, coverage OR-ed, counters summed, sizes checked.
// 8192^2 texels covered by one quad could need 67 M samples (5 GiB): refused with
// OUT_OF_MEMORY before a sample is allocated, both as a new lightmap and added to an atlas
// that already holds a small chart, which stays as it was.
TEST_F(LightmapAtlas, SamplesOverTheBudgetAreRefusedBeforeAllocating) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 0);
  LightmapsPtr lightmaps = new_lightmaps();
  bakegi_lightmaps* l = lightmaps.get();
  EXPECT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, floor.uvs.data(), 8192, 8192, nullptr),
            BAKEGI_ERROR_OUT_OF_MEMORY);
  EXPECT_NE(std::string(bakegi_last_error()).find("lower the texel density"), std::string::npos)
      << bakegi_last_error();
  EXPECT_EQ(bakegi_lightmaps_count(l), 0u);

  const std::vector<float> corner = floor.placed_uvs({0.01f, 0.01f}, {0.0f, 0.0f});
  ASSERT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, corner.data(), 8192, 8192, nullptr),
            BAKEGI_OK)
      << bakegi_last_error();
  bakegi_lightmap_info before{}, after{};
  ASSERT_EQ(bakegi_lightmaps_get_info(l, 0, &before), BAKEGI_OK);
  EXPECT_EQ(bakegi_lightmaps_add_to(l, 0, scene.get(), mesh, floor.uvs.data()),
            BAKEGI_ERROR_OUT_OF_MEMORY);
  ASSERT_EQ(bakegi_lightmaps_get_info(l, 0, &after), BAKEGI_OK);
  EXPECT_EQ(after.point_count, before.point_count);
}

TEST(LightmapAtlasMerge, AppendSamplesMergesAndChecksSizes) {
  auto planar = [](glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    LightmapTriangle t;
    const glm::vec2 uv[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      t.uv[k] = uv[k];
      t.p[k] = glm::vec3(uv[k], 0.0f);
      t.n[k] = glm::vec3(0.0f);
    }
    return t;
  };
  // Left column of a 2 x 2 map, then the lower right texel, each with a zero-area triangle.
  TexelSamples into =
      rasterize_texels({planar({0, 0}, {0.5f, 0}, {0.5f, 1}), planar({0, 0}, {0.5f, 1}, {0, 1}),
                        planar({0, 0}, {0.5f, 0}, {1, 0})},
                       2, 2, 1);
  TexelSamples more = rasterize_texels(
      {planar({0.5f, 0}, {1, 0}, {1, 0.5f}), planar({0.5f, 0}, {1, 0.5f}, {0.5f, 0.5f}),
       planar({0, 0}, {0, 0.5f}, {0, 1})},
      2, 2, 2);
  const size_t into_count = into.size(), more_count = more.size();
  ASSERT_EQ(into.covered_texels(), 2u);
  ASSERT_EQ(more.covered_texels(), 1u);
  ASSERT_EQ(into.skipped_degenerate_geometry, 1u);
  ASSERT_EQ(more.skipped_degenerate_geometry, 1u);
  append_samples(into, std::move(more));
  EXPECT_EQ(into.size(), into_count + more_count);
  EXPECT_EQ(into.points.positions.size(), into.size());
  EXPECT_EQ(into.face_normals.size(), into.size());
  EXPECT_EQ(into.weight.size(), into.size());
  EXPECT_EQ(into.covered_texels(), 3u);
  EXPECT_EQ(into.covered, (std::vector<uint8_t>{1, 1, 1, 0}));
  EXPECT_EQ(into.skipped_degenerate_geometry, 2u);
  EXPECT_EQ(into.points.object_ids.front(), 1u);
  EXPECT_EQ(into.points.object_ids.back(), 2u);

  TexelSamples other_size = rasterize_texels({planar({0, 0}, {1, 0}, {1, 1})}, 4, 2);
  EXPECT_THROW(append_samples(into, std::move(other_size)), Error);
  EXPECT_EQ(into.size(), into_count + more_count);  // unchanged by the refused merge
}

}  // namespace
}  // namespace bakegi::test
