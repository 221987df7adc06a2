// The lightmap C API end to end: texels of two meshes become one set of bake points, a fake
// bake result (a constant per lightmap) written as EXR reads back per lightmap within half
// precision, rejection drops the floor texels under a box, and misuse returns
// INVALID_ARGUMENT with a message (never a throw).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "bakegi/bakegi.h"
#include "bakegi/bakegi_handles.hpp"
#include "lightmap/exr_writer.h"
#include "lightmap_test_scene.h"

namespace bakegi::test {
namespace {

namespace fs = std::filesystem;

using LightmapApi = LightmapFilesTest;

// A fake bake result: `value` in every channel of each of the lightmaps' points.
std::vector<float> uniform_result(bakegi_lightmaps* lightmaps, float value) {
  bakegi_points* raw = nullptr;
  EXPECT_EQ(bakegi_lightmaps_get_points(lightmaps, &raw), BAKEGI_OK);
  PointsHandle points(raw);
  return std::vector<float>(3 * bakegi_points_count(points.get()), value);
}

TEST_F(LightmapApi, TwoLightmapsOneBakeRoundTrip) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const Quad wall({0, 2, 1}, {2, 0, 0}, {0, 0, 1});  // faces -y
  const uint32_t floor_mesh = floor.add_to(scene.get(), 10);
  const uint32_t wall_mesh = wall.add_to(scene.get(), 11);
  LightmapsPtr lightmaps = new_lightmaps();
  uint32_t first = 99, second = 99;
  ASSERT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene.get(), floor_mesh, floor.uvs.data(), 8, 8,
                                 &first),
            BAKEGI_OK)
      << bakegi_last_error();
  ASSERT_EQ(
      bakegi_lightmaps_add(lightmaps.get(), scene.get(), wall_mesh, wall.uvs.data(), 4, 2, &second),
      BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_EQ(first, 0u);
  EXPECT_EQ(second, 1u);
  EXPECT_EQ(bakegi_lightmaps_count(lightmaps.get()), 2u);

  bakegi_lightmap_info info0{}, info1{};
  ASSERT_EQ(bakegi_lightmaps_get_info(lightmaps.get(), 0, &info0), BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_get_info(lightmaps.get(), 1, &info1), BAKEGI_OK);
  EXPECT_EQ(info0.width, 8u);
  EXPECT_EQ(info0.covered_texels, 64u);
  EXPECT_EQ(info0.point_count, 72u);  // + the 8 diagonal texels' second samples
  EXPECT_EQ(info0.first_point, 0u);
  EXPECT_EQ(info0.skipped_triangles, 0u);
  EXPECT_EQ(info1.covered_texels, 8u);
  EXPECT_EQ(info1.first_point, 72u);

  bakegi_points* raw_points = nullptr;
  ASSERT_EQ(bakegi_lightmaps_get_points(lightmaps.get(), &raw_points), BAKEGI_OK);
  PointsHandle points(raw_points);
  const uint64_t count = bakegi_points_count(points.get());
  ASSERT_EQ(count, info0.point_count + info1.point_count);
  std::vector<float> normals(3 * count);
  std::vector<uint32_t> ids(count);
  ASSERT_EQ(bakegi_points_get(points.get(), nullptr, normals.data(), ids.data()), BAKEGI_OK);
  EXPECT_EQ(ids[0], 10u);
  EXPECT_EQ(ids[count - 1], 11u);
  EXPECT_FLOAT_EQ(normals[2], 1.0f);                     // floor: +z
  EXPECT_FLOAT_EQ(normals[3 * (count - 1) + 1], -1.0f);  // wall: -y

  // A fake bake result: one constant per lightmap.
  const glm::vec3 floor_value(0.25f, 0.5f, 1.5f), wall_value(3.0f, 0.125f, 7.0f);
  std::vector<float> rgb;
  for (uint64_t i = 0; i < count; ++i) {
    const glm::vec3 v = i < info0.point_count ? floor_value : wall_value;
    rgb.insert(rgb.end(), {v.x, v.y, v.z});
  }
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                       path("floor.exr").c_str(), 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_OK)
      << bakegi_last_error();
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 1, rgb.data(), count,
                                       path("wall.exr").c_str(), 2, 1, BAKEGI_EXR_PIZ),
            BAKEGI_OK)
      << bakegi_last_error();
  const RgbImage floor_image = read_exr(path("floor.exr"));
  ASSERT_EQ(floor_image.width, 8u);
  ASSERT_EQ(floor_image.height, 8u);
  for (const glm::vec3& p : floor_image.pixels) {
    // These values are exact in half; the weighted mean of equal values is within 1 ulp.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], floor_value[c], floor_value[c] * 0x1p-11f);
  }
  const RgbImage wall_image = read_exr(path("wall.exr"));
  ASSERT_EQ(wall_image.width, 4u);
  ASSERT_EQ(wall_image.height, 2u);
  for (const glm::vec3& p : wall_image.pixels) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[c], wall_value[c], wall_value[c] * 1e-6f);
  }
}

// The image resolved into the caller's memory is the one the EXR holds (full float: equal
// to the bit), bottom-up, with alpha 1 for RGBA; a wrong channel count or a buffer too small
// is refused before anything is written to it.
TEST_F(LightmapApi, ResolveIntoMemoryIsWhatTheExrHolds) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 10);
  LightmapsPtr lightmaps = new_lightmaps();
  ASSERT_EQ(
      bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, floor.uvs.data(), 6, 5, nullptr),
      BAKEGI_OK)
      << bakegi_last_error();
  bakegi_lightmap_info info{};
  ASSERT_EQ(bakegi_lightmaps_get_info(lightmaps.get(), 0, &info), BAKEGI_OK);
  bakegi_points* raw_points = nullptr;
  ASSERT_EQ(bakegi_lightmaps_get_points(lightmaps.get(), &raw_points), BAKEGI_OK);
  PointsHandle points(raw_points);
  const uint64_t count = info.point_count;
  std::vector<float> positions(3 * count);
  ASSERT_EQ(bakegi_points_get(points.get(), positions.data(), nullptr, nullptr), BAKEGI_OK);
  std::vector<float> rgb(3 * count);  // a field that varies over the floor: x, y, x + y
  for (uint64_t i = 0; i < count; ++i) {
    const float x = positions[3 * i], y = positions[3 * i + 1];
    rgb[3 * i] = x;
    rgb[3 * i + 1] = y;
    rgb[3 * i + 2] = x + y;
  }
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                       path("floor.exr").c_str(), 2, 1, BAKEGI_EXR_ZIP),
            BAKEGI_OK)
      << bakegi_last_error();
  const RgbImage file = read_exr(path("floor.exr"));
  const size_t pixels = size_t(info.width) * info.height;
  std::vector<float> rgba(4 * pixels, -1.0f);
  ASSERT_EQ(bakegi_lightmaps_resolve(lightmaps.get(), 0, rgb.data(), count, 2, 4, rgba.data(),
                                     rgba.size()),
            BAKEGI_OK)
      << bakegi_last_error();
  std::vector<float> rgb_image(3 * pixels, -1.0f);
  ASSERT_EQ(bakegi_lightmaps_resolve(lightmaps.get(), 0, rgb.data(), count, 2, 3, rgb_image.data(),
                                     rgb_image.size()),
            BAKEGI_OK);
  ASSERT_EQ(file.pixels.size(), pixels);
  for (size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(rgba[4 * i + c], file.pixels[i][c]) << "pixel " << i;
      EXPECT_EQ(rgb_image[3 * i + c], file.pixels[i][c]) << "pixel " << i;
    }
    EXPECT_EQ(rgba[4 * i + 3], 1.0f);
  }
  // Bottom-up: the floor's y grows with v, so the top row is greener than the bottom one.
  EXPECT_GT(rgba[4 * (pixels - 1) + 1], rgba[1]);

  std::vector<float> untouched(4 * pixels, -1.0f);
  EXPECT_EQ(bakegi_lightmaps_resolve(lightmaps.get(), 0, rgb.data(), count, 2, 2, untouched.data(),
                                     untouched.size()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_resolve(lightmaps.get(), 0, rgb.data(), count, 2, 4, untouched.data(),
                                     untouched.size() - 1),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("needs"), std::string::npos);
  EXPECT_EQ(bakegi_lightmaps_resolve(lightmaps.get(), 0, rgb.data(), count - 1, 2, 4,
                                     untouched.data(), untouched.size()),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_resolve(lightmaps.get(), 0, rgb.data(), count, 2, 4, nullptr, 0),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  for (float v : untouched) ASSERT_EQ(v, -1.0f);
}

// A chart covering only the lower-left quarter: the padding fills 2 texels around it, and
// the rest stays 0.
// The texel samples are refused before they are made when they could exceed the bake's
// budget; the default is the job's default (4096 MB).
TEST_F(LightmapApi, TheSampleBudgetIsTheBakes) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 10);
  LightmapsPtr lightmaps = new_lightmaps();
  // 2048 x 2048 texels: up to about 4.2 M samples of 76 bytes, over 1 MB, under 4096 MB.
  ASSERT_EQ(bakegi_lightmaps_set_memory_budget(lightmaps.get(), 1), BAKEGI_OK);
  EXPECT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, floor.uvs.data(), 2048, 2048,
                                 nullptr),
            BAKEGI_ERROR_OUT_OF_MEMORY);
  EXPECT_NE(std::string(bakegi_last_error()).find("more than the 1 MiB budget"), std::string::npos)
      << bakegi_last_error();
  EXPECT_EQ(bakegi_lightmaps_count(lightmaps.get()), 0u);  // nothing half added
  ASSERT_EQ(bakegi_lightmaps_set_memory_budget(lightmaps.get(), 4096), BAKEGI_OK);
  EXPECT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, floor.uvs.data(), 2048, 2048,
                                 nullptr),
            BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_EQ(bakegi_lightmaps_set_memory_budget(lightmaps.get(), 0), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_set_memory_budget(nullptr, 64), BAKEGI_ERROR_INVALID_ARGUMENT);
}

// Esc during a lightmap bake's texel work: bakegi_lightmaps_cancel from another thread stops
// a running add (a 2048^2 floor, about 4.2 M samples) within a texel row, adds nothing, and
// refuses every later add and rejection. The flag is sticky, so the outcome does not depend
// on when the worker gets to run.
TEST_F(LightmapApi, CancelStopsTheTexelWorkFromAnotherThread) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 10);
  LightmapsPtr lightmaps = new_lightmaps();
  bakegi_status added = BAKEGI_OK;
  std::chrono::steady_clock::time_point returned;
  std::thread worker([&] {
    added = bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, floor.uvs.data(), 2048, 2048,
                                 nullptr);
    returned = std::chrono::steady_clock::now();
  });
  ASSERT_EQ(bakegi_lightmaps_cancel(lightmaps.get()), BAKEGI_OK);
  const auto cancelled = std::chrono::steady_clock::now();
  worker.join();
  EXPECT_EQ(added, BAKEGI_ERROR_CANCELLED);
  std::printf("lightmap add returned %.1f ms after the cancel\n",
              1e3 * std::chrono::duration<double>(returned - cancelled).count());
  EXPECT_EQ(bakegi_lightmaps_count(lightmaps.get()), 0u);  // nothing half added
  EXPECT_EQ(
      bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, floor.uvs.data(), 8, 8, nullptr),
      BAKEGI_ERROR_CANCELLED);
  uint64_t rejected = 0;
  EXPECT_EQ(bakegi_lightmaps_reject_inside(lightmaps.get(), scene.get(), 0, 0, 0, &rejected),
            BAKEGI_ERROR_CANCELLED);
  EXPECT_EQ(bakegi_lightmaps_cancel(nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
}

// Esc during the write-back: the add-on writes the EXR on a worker thread, so a cancel can
// reach it. Resolving a 2048^2 floor (4.2 M samples) and writing it takes a measurable time
// (printed); once cancelled, the write stops between resolve's steps and leaves no file.
TEST_F(LightmapApi, CancelStopsTheWriteBack) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 10);
  LightmapsPtr lightmaps = new_lightmaps();
  ASSERT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, floor.uvs.data(), 2048, 2048,
                                 nullptr),
            BAKEGI_OK);
  const std::vector<float> rgb = uniform_result(lightmaps.get(), 0.5f);
  const uint64_t count = rgb.size() / 3;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                       path("whole.exr").c_str(), 4, 0, BAKEGI_EXR_ZIP),
            BAKEGI_OK)
      << bakegi_last_error();
  std::printf(
      "a 2048^2 lightmap resolved and written in %.0f ms\n",
      1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

  // A cancel from another thread while a write runs: it either finished first (OK, whole
  // file) or stopped (CANCELLED, no file); never a partial file.
  bakegi_status written = BAKEGI_OK;
  std::thread writer([&] {
    written = bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                         path("raced.exr").c_str(), 4, 0, BAKEGI_EXR_ZIP);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // into the write, usually
  ASSERT_EQ(bakegi_lightmaps_cancel(lightmaps.get()), BAKEGI_OK);
  const auto cancelled = std::chrono::steady_clock::now();
  writer.join();
  std::printf(
      "the write returned %s %.0f ms after the cancel\n",
      written == BAKEGI_OK ? "finished" : "cancelled",
      1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - cancelled).count());
  if (written == BAKEGI_OK) {
    EXPECT_EQ(read_exr(path("raced.exr")).width, 2048u);
  } else {
    EXPECT_EQ(written, BAKEGI_ERROR_CANCELLED) << bakegi_last_error();
    EXPECT_FALSE(std::filesystem::exists(path("raced.exr")));
  }
  // Cancelled is sticky: a later write stops before it starts, and writes nothing.
  EXPECT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                       path("after.exr").c_str(), 4, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_CANCELLED);
  EXPECT_FALSE(std::filesystem::exists(path("after.exr")));
}

TEST_F(LightmapApi, PaddingAroundAChart) {
  SceneHandle scene = lit_scene();
  Quad quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  for (float& uv : quad.uvs) uv *= 0.5f;
  const uint32_t mesh = quad.add_to(scene.get(), 0);
  LightmapsPtr lightmaps = new_lightmaps();
  ASSERT_EQ(
      bakegi_lightmaps_add(lightmaps.get(), scene.get(), mesh, quad.uvs.data(), 8, 8, nullptr),
      BAKEGI_OK);
  const std::vector<float> rgb = uniform_result(lightmaps.get(), 1.0f);
  const uint64_t count = rgb.size() / 3;
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                       path("chart.exr").c_str(), 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_OK)
      << bakegi_last_error();
  const RgbImage image = read_exr(path("chart.exr"));
  for (uint32_t y = 0; y < 8; ++y) {
    for (uint32_t x = 0; x < 8; ++x) {
      const float expected = x < 6 && y < 6 ? 1.0f : 0.0f;  // chart 4x4 + 2 texels
      EXPECT_EQ(image.pixels[y * 8 + x].x, expected) << x << "," << y;
    }
  }
}

TEST_F(LightmapApi, RejectsFloorTexelsUnderABox) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const uint32_t floor_mesh = floor.add_to(scene.get(), 0);
  // The box [-0.5,0.5]^2 x [-0.25,0.5], sunk into the floor, normals outwards.
  const std::vector<Quad> box = {
      Quad({0, 0, 0.5f}, {0.5f, 0, 0}, {0, 0.5f, 0}),
      Quad({0, 0, -0.25f}, {0, 0.5f, 0}, {0.5f, 0, 0}),
      Quad({0.5f, 0, 0.125f}, {0, 0.5f, 0}, {0, 0, 0.375f}),
      Quad({-0.5f, 0, 0.125f}, {0, 0, 0.375f}, {0, 0.5f, 0}),
      Quad({0, 0.5f, 0.125f}, {0, 0, 0.375f}, {0.5f, 0, 0}),
      Quad({0, -0.5f, 0.125f}, {0.5f, 0, 0}, {0, 0, 0.375f}),
  };
  for (const Quad& q : box) q.add_to(scene.get(), 1);
  LightmapsPtr lightmaps = new_lightmaps();
  ASSERT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene.get(), floor_mesh, floor.uvs.data(), 8, 8,
                                 nullptr),
            BAKEGI_OK);
  uint64_t rejected = 0;
  ASSERT_EQ(bakegi_lightmaps_reject_inside(lightmaps.get(), scene.get(), 0, 0, 0, &rejected),
            BAKEGI_OK)
      << bakegi_last_error();
  // Texels are 0.5 m: the 2 x 2 whose centres (+-0.25) lie under the box, 6 samples (two of
  // them are diagonal texels with 2 samples each); texels centred 0.25 m beside it stay.
  EXPECT_EQ(rejected, 6u);
  bakegi_lightmap_info info{};
  ASSERT_EQ(bakegi_lightmaps_get_info(lightmaps.get(), 0, &info), BAKEGI_OK);
  EXPECT_EQ(info.rejected_samples, 6u);
  EXPECT_EQ(info.covered_texels, 60u);
  EXPECT_EQ(info.point_count, 66u);

  // Written with padding, the rejected texels are filled from their neighbours.
  const std::vector<float> rgb(3 * info.point_count, 0.5f);
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), info.point_count,
                                       path("floor.exr").c_str(), 1, 0, BAKEGI_EXR_ZIP),
            BAKEGI_OK);
  const RgbImage image = read_exr(path("floor.exr"));
  for (const glm::vec3& p : image.pixels) EXPECT_EQ(p.x, 0.5f);
}

TEST_F(LightmapApi, ErrorsAreStatusesWithMessages) {
  SceneHandle scene = lit_scene();
  const Quad floor({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const uint32_t mesh = floor.add_to(scene.get(), 0);
  EXPECT_EQ(bakegi_lightmaps_create(nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  LightmapsPtr lightmaps = new_lightmaps();
  bakegi_lightmaps* l = lightmaps.get();
  const float* uvs = floor.uvs.data();

  EXPECT_EQ(bakegi_lightmaps_add(nullptr, scene.get(), mesh, uvs, 4, 4, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_add(l, nullptr, mesh, uvs, 4, 4, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, nullptr, 4, 4, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("lightmap_uvs is NULL"), std::string::npos);
  EXPECT_EQ(bakegi_lightmaps_add(l, scene.get(), 5, uvs, 4, 4, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("mesh 5"), std::string::npos);
  EXPECT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, uvs, 0, 4, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, uvs, 4, 100000, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  std::vector<float> nan_uvs = floor.uvs;
  nan_uvs[3] = NAN;
  EXPECT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, nan_uvs.data(), 4, 4, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_count(l), 0u);  // failed adds add nothing

  bakegi_points* points = reinterpret_cast<bakegi_points*>(1);
  EXPECT_EQ(bakegi_lightmaps_get_points(l, &points), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(points, nullptr);
  bakegi_lightmap_info info{};
  EXPECT_EQ(bakegi_lightmaps_get_info(l, 0, &info), BAKEGI_ERROR_INVALID_ARGUMENT);

  ASSERT_EQ(bakegi_lightmaps_add(l, scene.get(), mesh, uvs, 4, 4, nullptr), BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_get_info(l, 0, &info), BAKEGI_OK);
  std::vector<float> rgb(3 * info.point_count, 1.0f);
  const uint64_t n = info.point_count;
  const std::string out = path("x.exr");
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n - 1, out.c_str(), 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("count"), std::string::npos);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 1, rgb.data(), n, out.c_str(), 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, nullptr, n, out.c_str(), 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, nullptr, 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, "", 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, out.c_str(), 5000, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, out.c_str(), 2, 2, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, out.c_str(), 2, 0, 9u),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  rgb[4] = NAN;
  EXPECT_EQ(bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, out.c_str(), 2, 0, BAKEGI_EXR_ZIP),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("point 1"), std::string::npos);
  rgb[4] = 1.0f;
  const std::string unwritable = path("missing/dir/x.exr");
  EXPECT_EQ(
      bakegi_lightmaps_write_exr(l, 0, rgb.data(), n, unwritable.c_str(), 2, 0, BAKEGI_EXR_ZIP),
      BAKEGI_ERROR_IO);
  EXPECT_NE(std::string(bakegi_last_error()).find(unwritable), std::string::npos);
  EXPECT_FALSE(fs::exists(out));

  EXPECT_EQ(bakegi_lightmaps_reject_inside(l, nullptr, 0, 0, 0, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_reject_inside(l, scene.get(), 0, 2.0f, 0, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_count(nullptr), 0u);
  bakegi_lightmaps_destroy(nullptr);
}

}  // namespace
}  // namespace bakegi::test
