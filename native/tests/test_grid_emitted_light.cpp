// bakegi_grid_with_emitted_light: the web page's grid (the bounced light plus the world's and
// emitters' direct light the grid carries) against a closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "capi_test_scene.h"

namespace bakegi {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// View factor from a point to a parallel rectangle a x b whose corner lies straight above it
// at height h.
double corner_rectangle_factor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
          y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
         (2 * kPiD);
}

// A grid baked under a sky keeps the sky's direct light apart (bakes and Apply Grid read
// only the bounced light); the page's grid adds it. The unit box without its ceiling, black
// (nothing bounces), under a sky Lw: at the floor's centre the grid reads its four vertices
// nearest the floor, (0.375 | 0.625, 0.375 | 0.625, 0.125) in 25 cm cells, which see the sky
// through the opening 0.875 above them with the view factor of four corner rectangles of
// 0.375 and 0.625 m sides. The page's grid there reads Lw times that, the bake's grid 0.
TEST(GridEmittedLight, ThePagesGridAddsItToTheBouncedLight) {
  test::ScenePtr scene = test::new_scene();
  const bakegi_material_desc black = test::grey_material(0.0f);
  ASSERT_EQ(bakegi_scene_add_material(scene.get(), &black, nullptr), BAKEGI_OK);
  test::BoxMesh box;
  box.indices.erase(box.indices.begin() + 6, box.indices.begin() + 12);  // the ceiling
  const bakegi_mesh_desc mesh = box.desc();
  ASSERT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  const float sky = 0.5f, world[3] = {sky, sky, sky};
  ASSERT_EQ(bakegi_scene_set_world(scene.get(), world), BAKEGI_OK);
  const float bounds_min[3] = {0, 0, 0}, bounds_max[3] = {1, 1, 1};
  bakegi_grid* layout_raw = nullptr;
  ASSERT_EQ(bakegi_grid_create(bounds_min, bounds_max, 0.25f, 0, &layout_raw), BAKEGI_OK);
  const GridHandle layout(layout_raw);
  bakegi_job* job_raw = nullptr;
  ASSERT_EQ(
      bakegi_job_start_grid(scene.get(), layout.get(), 1024, test::new_settings().get(), &job_raw),
      BAKEGI_OK)
      << bakegi_last_error();
  const JobHandle job(job_raw);
  ASSERT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << bakegi_last_error();
  bakegi_grid* baked_raw = nullptr;
  ASSERT_EQ(bakegi_job_get_grid(job.get(), &baked_raw), BAKEGI_OK);
  const GridHandle baked(baked_raw);
  bakegi_grid* page_raw = nullptr;
  int has_emitted = -1;
  ASSERT_EQ(bakegi_grid_with_emitted_light(baked.get(), &page_raw, &has_emitted), BAKEGI_OK);
  const GridHandle page(page_raw);
  EXPECT_EQ(has_emitted, 1);
  const float position[3] = {0.5f, 0.5f, 0.0f}, normal[3] = {0, 0, 1};
  float bounced[3], page_light[3];
  ASSERT_EQ(bakegi_grid_evaluate(baked.get(), position, normal, 1, BAKEGI_GRID_TRILINEAR,
                                 BAKEGI_GRID_SQUARED, bounced),
            BAKEGI_OK);
  ASSERT_EQ(bakegi_grid_evaluate(page.get(), position, normal, 1, BAKEGI_GRID_TRILINEAR,
                                 BAKEGI_GRID_SQUARED, page_light),
            BAKEGI_OK);
  const double factor = 2.0 * corner_rectangle_factor(0.375, 0.625, 0.875) +
                        corner_rectangle_factor(0.375, 0.375, 0.875) +
                        corner_rectangle_factor(0.625, 0.625, 0.875);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(bounced[c], 0.0f);
    // 1024 Owen-scrambled Sobol' rays a hemisphere across the opening's edges: 2%.
    EXPECT_NEAR(page_light[c], sky * factor, 0.02 * sky * factor) << c;
  }
  // A grid without emitted light comes back as it is.
  bakegi_grid* again_raw = nullptr;
  ASSERT_EQ(bakegi_grid_with_emitted_light(page.get(), &again_raw, &has_emitted), BAKEGI_OK);
  const GridHandle again(again_raw);
  EXPECT_EQ(has_emitted, 0);
  // Asked alone (no copy): the baked grid holds emitted light.
  EXPECT_EQ(bakegi_grid_with_emitted_light(baked.get(), nullptr, &has_emitted), BAKEGI_OK);
  EXPECT_EQ(has_emitted, 1);
  EXPECT_EQ(bakegi_grid_with_emitted_light(nullptr, &page_raw, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
}

}  // namespace
}  // namespace bakegi
