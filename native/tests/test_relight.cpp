// Relighting without relinking (Antiradiance §3.3) through the C API: a relight reuses the
// previous bake's hierarchy and links, so with the same settings it must give exactly what a
// full bake of the changed scene gives; it must refuse a scene whose geometry changed and
// methods that keep nothing to relight from.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "capi_test_scene.h"

namespace bakegi::test {
namespace {

constexpr size_t kPoints = 64;

SettingsPtr small_antiradiance_settings() {
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_string(settings.get(), "method", "antiradiance"), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "bins", 48), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_set_float(settings.get(), "patch_size", 0.25), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "direct_samples", 16), BAKEGI_OK);
  return settings;
}

std::vector<float> result_of(bakegi_job* job) {
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_OK) << last_error();
  std::vector<float> rgb(3 * kPoints);
  EXPECT_EQ(bakegi_job_get_result(job, rgb.data(), kPoints), BAKEGI_OK) << last_error();
  return rgb;
}

std::string report_of(const bakegi_job* job) {
  size_t length = 0;
  EXPECT_EQ(bakegi_job_get_report(job, nullptr, 0, &length), BAKEGI_OK);
  std::string report(length + 1, '\0');
  EXPECT_EQ(bakegi_job_get_report(job, report.data(), report.size(), &length), BAKEGI_OK);
  return report;
}

JobPtr bake(const bakegi_scene* scene, const bakegi_points* points,
            const bakegi_settings* settings) {
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start(scene, points, settings, &job), BAKEGI_OK) << last_error();
  return JobPtr(job);
}

JobPtr relight(const bakegi_job* previous, const bakegi_scene* scene) {
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start_relight(previous, scene, nullptr, nullptr, &job), BAKEGI_OK)
      << last_error();
  return JobPtr(job);
}

// Replaces the box scene's light by a point light at (x, y, z) of `intensity` W/sr.
void set_light(bakegi_scene* scene, float x, float y, float z, float intensity) {
  ASSERT_EQ(bakegi_scene_clear_lights(scene), BAKEGI_OK);
  const bakegi_light_desc light = point_light(x, y, z, intensity);
  ASSERT_EQ(bakegi_scene_add_light(scene, &light, nullptr), BAKEGI_OK);
}

double largest_relative_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double largest = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double scale = std::max(std::abs(double(b[i])), 1e-12);
    largest = std::max(largest, std::abs(double(a[i]) - double(b[i])) / scale);
  }
  return largest;
}

TEST(Relight, MovedLightGivesExactlyTheFullBakeOfTheMovedScene) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = small_antiradiance_settings();
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  const std::vector<float> before = result_of(first.get());
  ASSERT_EQ(bakegi_job_can_relight(first.get()), 1);

  set_light(scene.get(), 0.3f, 0.6f, 0.8f, 1.0f);
  JobPtr relit = relight(first.get(), scene.get());
  const std::vector<float> after = result_of(relit.get());
  JobPtr fresh = bake(scene.get(), points.get(), settings.get());
  const std::vector<float> expected = result_of(fresh.get());

  // Same hierarchy, links, seed and thread-count-independent passes: the same numbers.
  EXPECT_EQ(after, expected);
  // And the light did move: the floor below the old position is lit differently.
  EXPECT_GT(largest_relative_difference(after, before), 0.05);

  const std::string report = report_of(relit.get());
  EXPECT_NE(report.find("\"relight\": 1"), std::string::npos) << report;
  // The same scene handle with new lights: the relight shares the bake's mesh storage.
  EXPECT_NE(report.find("\"relight_shared_geometry\": 1"), std::string::npos) << report;
  // Relighting does not link again, so the report has no linking time.
  EXPECT_EQ(report.find("antiradiance_linking"), std::string::npos) << report;
}

// A scene built again with the same geometry (another handle: no shared storage) is compared
// by value and relit all the same, to the same numbers.
TEST(Relight, AnEqualSceneFromAnotherHandleIsComparedByValue) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = small_antiradiance_settings();
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  result_of(first.get());
  ScenePtr again = new_box_scene();
  set_light(scene.get(), 0.3f, 0.6f, 0.8f, 1.0f);
  set_light(again.get(), 0.3f, 0.6f, 0.8f, 1.0f);
  JobPtr same_handle = relight(first.get(), scene.get());
  JobPtr other_handle = relight(first.get(), again.get());
  EXPECT_EQ(result_of(other_handle.get()), result_of(same_handle.get()));
  const std::string report = report_of(other_handle.get());
  EXPECT_NE(report.find("\"relight_shared_geometry\": 0"), std::string::npos) << report;
}

TEST(Relight, DoublingTheLightDoublesTheIndirectLight) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = small_antiradiance_settings();
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  const std::vector<float> once = result_of(first.get());

  set_light(scene.get(), 0.5f, 0.5f, 0.5f, 2.0f);
  JobPtr relit = relight(first.get(), scene.get());
  const std::vector<float> twice = result_of(relit.get());
  // Transport is linear in the emitters; the direct-light samples are the same stream, so
  // only float rounding separates 2·x from the relit value.
  for (size_t i = 0; i < once.size(); ++i) {
    EXPECT_NEAR(twice[i], 2.0f * once[i], 1e-5f * std::abs(2.0f * once[i]) + 1e-12f) << i;
  }
}

TEST(Relight, PreviousJobMayBeDestroyedWhileTheRelightRuns) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = small_antiradiance_settings();
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  const std::vector<float> before = result_of(first.get());
  JobPtr relit = relight(first.get(), scene.get());
  first.reset();
  EXPECT_EQ(result_of(relit.get()), before);
}

TEST(Relight, SettingsOfTheSolveMayChangeThoseOfThePrecomputationMayNot) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = small_antiradiance_settings();
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "iterations", 1), BAKEGI_OK);
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  const std::vector<float> one_bounce = result_of(first.get());

  // More iterations: the relight equals a full bake with those settings.
  SettingsPtr more = new_settings(nullptr);
  ASSERT_EQ(bakegi_settings_set_int(more.get(), "iterations", 8), BAKEGI_OK);
  bakegi_job* raw = nullptr;
  ASSERT_EQ(bakegi_job_start_relight(first.get(), scene.get(), nullptr, more.get(), &raw),
            BAKEGI_OK)
      << last_error();
  JobPtr relit(raw);
  const std::vector<float> eight = result_of(relit.get());
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "iterations", 8), BAKEGI_OK);
  JobPtr fresh = bake(scene.get(), points.get(), settings.get());
  EXPECT_EQ(eight, result_of(fresh.get()));
  EXPECT_NE(eight, one_bounce);

  // The bin count shaped the links: refused, naming the key.
  SettingsPtr bins = new_settings(nullptr);
  ASSERT_EQ(bakegi_settings_set_int(bins.get(), "bins", 192), BAKEGI_OK);
  raw = nullptr;
  EXPECT_EQ(bakegi_job_start_relight(first.get(), scene.get(), nullptr, bins.get(), &raw),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(raw, nullptr);
  EXPECT_NE(last_error().find("\"bins\""), std::string::npos) << last_error();
}

TEST(Relight, ChangedGeometryIsRefusedWithAClearMessage) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = small_antiradiance_settings();
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  result_of(first.get());

  const BoxMesh box;
  const bakegi_mesh_desc second = box.desc(0, 1);
  ASSERT_EQ(bakegi_scene_add_mesh(scene.get(), &second, nullptr), BAKEGI_OK);
  JobPtr relit = relight(first.get(), scene.get());
  EXPECT_EQ(bakegi_job_wait(relit.get()), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("geometry or materials differ"), std::string::npos) << last_error();
}

TEST(Relight, MethodsWithoutPrecomputationCannotRelight) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(kPoints);
  SettingsPtr settings = new_settings();
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "samples", 1), BAKEGI_OK);
  JobPtr first = bake(scene.get(), points.get(), settings.get());
  result_of(first.get());
  EXPECT_EQ(bakegi_job_can_relight(first.get()), 0);
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start_relight(first.get(), scene.get(), nullptr, nullptr, &job),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(job, nullptr);
  EXPECT_NE(last_error().find("relight"), std::string::npos) << last_error();
}

TEST(Relight, UnfinishedOrMissingJobsAreRefused) {
  ScenePtr scene = new_box_scene();
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start_relight(nullptr, scene.get(), nullptr, nullptr, &job),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  JobPtr running(start_endless_job(16));
  EXPECT_EQ(bakegi_job_can_relight(running.get()), 0);
  EXPECT_EQ(bakegi_job_start_relight(running.get(), scene.get(), nullptr, nullptr, &job),
            BAKEGI_ERROR_NOT_READY);
  EXPECT_EQ(job, nullptr);
  bakegi_job_cancel(running.get());
  EXPECT_EQ(bakegi_job_wait(running.get()), BAKEGI_ERROR_CANCELLED);
  EXPECT_EQ(bakegi_job_start_relight(running.get(), scene.get(), nullptr, nullptr, &job),
            BAKEGI_ERROR_INVALID_ARGUMENT);
}

TEST(SceneLights, GetReturnsWhatWasAddedAndClearRemovesAll) {
  ScenePtr scene = new_box_scene();
  bakegi_light_desc spot{};
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.position[2] = 0.9f;
  spot.direction[2] = -1.0f;
  spot.color[0] = 3.0f;
  spot.spot_size = 1.0f;
  spot.spot_blend = 0.25f;
  spot.axis_u[0] = 1.0f;
  ASSERT_EQ(bakegi_scene_add_light(scene.get(), &spot, nullptr), BAKEGI_OK);
  bakegi_light_desc back{};
  ASSERT_EQ(bakegi_scene_get_light(scene.get(), 1, &back), BAKEGI_OK);
  EXPECT_EQ(back.type, BAKEGI_LIGHT_SPOT);
  EXPECT_EQ(back.position[2], 0.9f);
  EXPECT_EQ(back.direction[2], -1.0f);
  EXPECT_EQ(back.color[0], 3.0f);
  EXPECT_EQ(back.spot_size, 1.0f);
  EXPECT_EQ(back.spot_blend, 0.25f);
  EXPECT_EQ(bakegi_scene_get_light(scene.get(), 2, &back), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(last_error().find("light index 2"), std::string::npos) << last_error();
  ASSERT_EQ(bakegi_scene_clear_lights(scene.get()), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_light_count(scene.get()), 0u);
}

}  // namespace
}  // namespace bakegi::test
