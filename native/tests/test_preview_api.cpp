// bakegi_preview_*: the splatting preview through the C API refuses bad input with a
// message, never crashes, and renders a lit box.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "capi_test_scene.h"

namespace bakegi::test {
namespace {

// Inside the unit box (capi_test_scene.h), looking along +y from its front.
const float kCamera[12] = {0.5f,       0.05f, 0.5f, 0.7071068f, 0.0f, 0.0f,
                           0.7071068f, 1.2f,  0.0f, 0.0f,       0.0f, 0.0f};

PreviewHandle new_preview(const bakegi_scene* scene) {
  bakegi_preview* preview = nullptr;
  EXPECT_EQ(bakegi_preview_create(scene, &preview), BAKEGI_OK) << last_error();
  return PreviewHandle(preview);
}

TEST(PreviewApi, RendersALitBoxWithDirectAndIndirectLight) {
  const ScenePtr scene = new_box_scene();
  const PreviewHandle preview = new_preview(scene.get());
  ASSERT_EQ(bakegi_preview_set_lights(preview.get(), scene.get()), BAKEGI_OK);
  const uint32_t w = 32, h = 24;
  std::vector<float> rgba(4 * w * h), direct(3 * w * h), indirect(3 * w * h);
  std::vector<uint8_t> levels(w * h);
  const SettingsPtr settings = new_settings("splatting");
  ASSERT_EQ(bakegi_preview_render(preview.get(), kCamera, w, h, settings.get(), rgba.data(),
                                  direct.data(), indirect.data(), levels.data()),
            BAKEGI_OK)
      << last_error();
  double direct_sum = 0.0, indirect_sum = 0.0;
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    ASSERT_EQ(rgba[4 * i + 3], 1.0f);  // the box surrounds the camera
    ASSERT_LT(levels[i], 255);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(rgba[4 * i + c]));
      direct_sum += direct[3 * i + c];
      indirect_sum += indirect[3 * i + c];
    }
  }
  EXPECT_GT(direct_sum, 0.0);
  EXPECT_GT(indirect_sum, 0.0);
  size_t length = 0;
  ASSERT_EQ(bakegi_preview_get_report(preview.get(), nullptr, 0, &length), BAKEGI_OK);
  EXPECT_GT(length, 50u);
}

TEST(PreviewApi, RefusesBadInputWithAMessage) {
  const ScenePtr scene = new_box_scene();
  bakegi_preview* none = nullptr;
  EXPECT_EQ(bakegi_preview_create(nullptr, &none), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_preview_create(scene.get(), nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  const ScenePtr empty = new_scene();
  EXPECT_NE(bakegi_preview_create(empty.get(), &none), BAKEGI_OK);  // nothing to see
  EXPECT_EQ(none, nullptr);
  const PreviewHandle preview = new_preview(scene.get());
  std::vector<float> rgba(4 * 16);
  EXPECT_EQ(bakegi_preview_render(preview.get(), nullptr, 4, 4, nullptr, rgba.data(), nullptr,
                                  nullptr, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_preview_render(preview.get(), kCamera, 0, 4, nullptr, rgba.data(), nullptr,
                                  nullptr, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  float zero_rotation[12] = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0};
  EXPECT_EQ(bakegi_preview_render(preview.get(), zero_rotation, 4, 4, nullptr, rgba.data(), nullptr,
                                  nullptr, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("quaternion"), std::string::npos) << last_error();
  float nan_camera[12];
  std::copy(kCamera, kCamera + 12, nan_camera);
  nan_camera[1] = std::nanf("");
  EXPECT_EQ(bakegi_preview_render(preview.get(), nan_camera, 4, 4, nullptr, rgba.data(), nullptr,
                                  nullptr, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  const SettingsPtr other = new_settings("splatting");
  ASSERT_EQ(bakegi_settings_set_int(other.get(), "bins", 10), BAKEGI_OK);
  EXPECT_EQ(bakegi_preview_render(preview.get(), kCamera, 4, 4, other.get(), rgba.data(), nullptr,
                                  nullptr, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("bins"), std::string::npos) << last_error();
  EXPECT_EQ(bakegi_preview_set_lights(preview.get(), nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_preview_get_report(nullptr, nullptr, 0, nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  bakegi_preview_destroy(nullptr);  // a no-op, as for every handle
}

}  // namespace
}  // namespace bakegi::test
