// The C API under misuse, as a careless or hostile caller would: dead handles, handles of
// the wrong kind, double destroy, cancel and wait in every order, a scene destroyed under its
// job, two jobs on one scene, absurd settings and degenerate scenes. Each gets a clear error
// or a correct result, never a crash (these run under ASan and UBSan in CI) or a hang.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "capi_test_scene.h"

namespace bakegi::test {
namespace {

#define EXPECT_REFUSED(call, status, expected)                                    \
  do {                                                                            \
    EXPECT_EQ((call), (status)) << bakegi_last_error();                           \
    EXPECT_NE(std::string(bakegi_last_error()).find(expected), std::string::npos) \
        << "message: " << bakegi_last_error();                                    \
  } while (0)

constexpr auto kInvalid = BAKEGI_ERROR_INVALID_ARGUMENT;

std::vector<float> run_to_end(bakegi_scene* scene, bakegi_points* points,
                              bakegi_settings* settings) {
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start(scene, points, settings, &job), BAKEGI_OK) << bakegi_last_error();
  JobPtr owned(job);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
  std::vector<float> rgb(3 * bakegi_points_count(points));
  EXPECT_EQ(bakegi_job_get_result(job, rgb.data(), bakegi_points_count(points)), BAKEGI_OK);
  return rgb;
}

// A bake's outcome: refused at start, or failed (or not) when it ran (scenes are validated
// on the job's thread).
bakegi_status bake_status(bakegi_scene* scene, bakegi_points* points, bakegi_settings* settings) {
  bakegi_job* job = nullptr;
  const bakegi_status started = bakegi_job_start(scene, points, settings, &job);
  if (started != BAKEGI_OK) return started;
  JobPtr owned(job);
  return bakegi_job_wait(job);
}

// A destroyed handle is refused by name (the registry is read, never the freed memory),
// destroying it again does nothing, and the value-returning calls read it as empty.
TEST(ApiMisuse, DestroyedHandlesAreRefusedNotUsed) {
  bakegi_scene* scene = nullptr;
  ASSERT_EQ(bakegi_scene_create(&scene), BAKEGI_OK);
  bakegi_scene_destroy(scene);
  const bakegi_material_desc material = grey_material();
  EXPECT_REFUSED(bakegi_scene_add_material(scene, &material, nullptr), kInvalid,
                 "scene is not a live scene handle");
  EXPECT_EQ(bakegi_scene_triangle_count(scene), 0u);
  EXPECT_EQ(bakegi_scene_light_count(scene), 0u);
  bakegi_scene_destroy(scene);  // twice: nothing happens, the error says so
  EXPECT_NE(std::string(bakegi_last_error()).find("destroyed already"), std::string::npos);

  bakegi_settings* settings = nullptr;
  ASSERT_EQ(bakegi_settings_create(&settings), BAKEGI_OK);
  bakegi_settings_destroy(settings);
  EXPECT_REFUSED(bakegi_settings_set_int(settings, "samples", 4), kInvalid, "not a live");
  bakegi_settings_destroy(settings);

  bakegi_job* job = start_endless_job(4);
  bakegi_job_cancel(job);
  bakegi_job_destroy(job);
  bakegi_job_cancel(job);  // void calls on a dead job do nothing
  EXPECT_EQ(bakegi_job_is_done(job), 1);
  EXPECT_EQ(bakegi_job_progress(job), 0.0);
  EXPECT_EQ(bakegi_job_can_relight(job), 0);
  char stage[32] = "x";
  bakegi_job_stage(job, stage, sizeof stage);
  EXPECT_STREQ(stage, "");
  EXPECT_REFUSED(bakegi_job_wait(job), kInvalid, "job is not a live job handle");
  bakegi_job_destroy(job);
}

// A pointer of another kind (a C caller's cast) or one the library never made.
TEST(ApiMisuse, HandlesOfAnotherKindOrForeignPointersAreRefused) {
  PointsPtr points = new_floor_points(4);
  auto* as_scene = reinterpret_cast<bakegi_scene*>(points.get());
  EXPECT_REFUSED(bakegi_scene_validate(as_scene), kInvalid, "is a points handle, not a scene");
  bakegi_scene_destroy(as_scene);  // not destroyed as a scene: the points stay usable
  EXPECT_EQ(bakegi_points_count(points.get()), 4u);
  std::vector<uint8_t> junk(256, 0xAB);
  auto* foreign = reinterpret_cast<bakegi_settings*>(junk.data());
  EXPECT_REFUSED(bakegi_settings_check(foreign), kInvalid, "not made by this library");
  bakegi_settings_destroy(foreign);  // not freed: junk is ours
}

// Cancel and wait in every order: cancel twice, wait twice, wait after cancel, cancel after
// the end, destroy without waiting. Each returns; the statuses say what happened.
TEST(ApiMisuse, CancelAndWaitInAnyOrder) {
  bakegi_job* job = start_endless_job(16);
  bakegi_job_cancel(job);
  bakegi_job_cancel(job);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_ERROR_CANCELLED);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_ERROR_CANCELLED);
  EXPECT_EQ(bakegi_job_is_done(job), 1);
  std::vector<float> rgb(3 * 16);
  EXPECT_EQ(bakegi_job_get_result(job, rgb.data(), 16), BAKEGI_ERROR_CANCELLED);
  bakegi_job_cancel(job);
  bakegi_job_destroy(job);

  // Destroyed while running: destroy cancels and joins.
  bakegi_job_destroy(start_endless_job(16));

  // Finished, then cancelled: the result stays.
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(8);
  SettingsPtr settings = new_settings();
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "samples", 4), BAKEGI_OK);
  bakegi_job* done = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &done), BAKEGI_OK);
  JobPtr owned(done);
  ASSERT_EQ(bakegi_job_wait(done), BAKEGI_OK);
  bakegi_job_cancel(done);
  EXPECT_EQ(bakegi_job_wait(done), BAKEGI_OK);
  EXPECT_EQ(bakegi_job_get_result(done, rgb.data(), 8), BAKEGI_OK);
}

// A job keeps its own copy: its scene, points and settings may be destroyed while it runs,
// and two jobs may bake one scene at once (same seed, same result as one alone).
TEST(ApiMisuse, ScenesDestroyedUnderTheirJobAndSharedByTwoJobs) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(32);
  SettingsPtr settings = new_settings();
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "samples", 16), BAKEGI_OK);
  const std::vector<float> alone = run_to_end(scene.get(), points.get(), settings.get());

  bakegi_job *first = nullptr, *second = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &first), BAKEGI_OK);
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &second), BAKEGI_OK);
  JobPtr a(first), b(second);
  scene.reset();
  points.reset();
  settings.reset();
  ASSERT_EQ(bakegi_job_wait(first), BAKEGI_OK) << bakegi_last_error();
  ASSERT_EQ(bakegi_job_wait(second), BAKEGI_OK) << bakegi_last_error();
  std::vector<float> one(alone.size()), two(alone.size());
  ASSERT_EQ(bakegi_job_get_result(first, one.data(), 32), BAKEGI_OK);
  ASSERT_EQ(bakegi_job_get_result(second, two.data(), 32), BAKEGI_OK);
  EXPECT_EQ(one, alone);
  EXPECT_EQ(two, alone);
}

// Absurd settings are refused at start, naming the key and the allowed range.
TEST(ApiMisuse, AbsurdSettingsAreRefusedByName) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(4);
  struct Case {
    const char* method;
    const char* key;
    int64_t value;
  };
  for (const Case& c :
       {Case{"antiradiance", "bins", 0}, Case{"antiradiance", "bins", 1000000000},
        Case{"pathtrace", "samples", -1}, Case{"pathtrace", "threads", 1000000},
        Case{"pathtrace", "memory_budget_mb", 0}, Case{"meshless", "gather_rays", 0},
        Case{"pathtrace", "max_bounces", int64_t(1) << 20}}) {
    SettingsPtr settings = new_settings(c.method);
    ASSERT_EQ(bakegi_settings_set_int(settings.get(), c.key, c.value), BAKEGI_OK);
    bakegi_job* job = nullptr;
    EXPECT_REFUSED(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), kInvalid,
                   std::string("setting \"") + c.key + "\" must be in [");
    EXPECT_EQ(job, nullptr);
  }
}

// Degenerate scenes: clear refusals, or a correct bake where the scene is legitimate.
TEST(ApiMisuse, DegenerateScenes) {
  PointsPtr points = new_floor_points(4);
  SettingsPtr settings = new_settings();
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "samples", 4), BAKEGI_OK);

  ScenePtr empty = new_scene();
  EXPECT_EQ(bake_status(empty.get(), points.get(), settings.get()), BAKEGI_ERROR_INVALID_SCENE);
  EXPECT_NE(std::string(bakegi_last_error()).find("triangle"), std::string::npos)
      << bakegi_last_error();

  // Every triangle degenerate (three collinear corners).
  ScenePtr flat = new_scene();
  const bakegi_material_desc grey = grey_material();
  ASSERT_EQ(bakegi_scene_add_material(flat.get(), &grey, nullptr), BAKEGI_OK);
  const float line[] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
  const uint32_t corners[] = {0, 1, 2, 2, 1, 0};
  bakegi_mesh_desc mesh{};
  mesh.positions = line;
  mesh.vertex_count = 3;
  mesh.indices = corners;
  mesh.triangle_count = 2;
  ASSERT_EQ(bakegi_scene_add_mesh(flat.get(), &mesh, nullptr), BAKEGI_OK);
  const bakegi_light_desc lamp = point_light(0.5f, 0.5f, 0.5f, 1.0f);
  ASSERT_EQ(bakegi_scene_add_light(flat.get(), &lamp, nullptr), BAKEGI_OK);
  EXPECT_EQ(bake_status(flat.get(), points.get(), settings.get()), BAKEGI_ERROR_INVALID_SCENE);
  EXPECT_NE(std::string(bakegi_last_error()).find("triangle"), std::string::npos)
      << bakegi_last_error();

  // Emitters only: the box's own walls glow and nothing else lights it. Legitimate: the
  // floor receives the walls' light bounced once more (positive, finite).
  ScenePtr glowing = new_scene();
  bakegi_material_desc emitter = grey_material();
  emitter.emission[0] = emitter.emission[1] = emitter.emission[2] = 1.0f;
  ASSERT_EQ(bakegi_scene_add_material(glowing.get(), &emitter, nullptr), BAKEGI_OK);
  const BoxMesh box;
  const bakegi_mesh_desc box_mesh = box.desc();
  ASSERT_EQ(bakegi_scene_add_mesh(glowing.get(), &box_mesh, nullptr), BAKEGI_OK);
  for (float v : run_to_end(glowing.get(), points.get(), settings.get())) {
    EXPECT_TRUE(std::isfinite(v) && v > 0.0f) << v;
  }

  // Coordinates of 1e30 (beyond what floats can bake) are refused where they enter.
  ScenePtr huge = new_scene();
  ASSERT_EQ(bakegi_scene_add_material(huge.get(), &grey, nullptr), BAKEGI_OK);
  std::vector<float> far = box.positions;
  for (float& v : far) v *= 1e30f;
  bakegi_mesh_desc far_mesh = box.desc();
  far_mesh.positions = far.data();
  EXPECT_REFUSED(bakegi_scene_add_mesh(huge.get(), &far_mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
                 "mesh 0");
}

// Bake points in open space (a scripted bake's stray points): antiradiance used to give a
// point a million metres from the box the light of its nearest patch. Off every surface it
// now gathers from the solution (the box is closed: its outside reflects nothing, so 0);
// without the gather it keeps the nearest patch's value and says so in a warning.
TEST(ApiMisuse, AntiradianceGivesNoLightToPointsInOpenSpace) {
  ScenePtr scene = new_box_scene();
  const float positions[] = {0.5f, 0.5f, 0.0f, 1e6f, 0.5f, 0.5f};
  const float normals[] = {0.0f, 0.0f, 1.0f, -1.0f, 0.0f, 0.0f};
  bakegi_points* raw = nullptr;
  ASSERT_EQ(bakegi_points_create(positions, normals, nullptr, 2, &raw), BAKEGI_OK);
  PointsPtr points(raw);
  for (const int64_t rays : {int64_t(64), int64_t(0)}) {
    SettingsPtr settings = new_settings("antiradiance");
    ASSERT_EQ(bakegi_settings_set_int(settings.get(), "bins", 48), BAKEGI_OK);
    ASSERT_EQ(bakegi_settings_set_int(settings.get(), "near_field_rays", rays), BAKEGI_OK);
    ASSERT_EQ(bakegi_settings_set_int(settings.get(), "error_probes", 0), BAKEGI_OK);
    bakegi_job* job = nullptr;
    ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
    JobPtr owned(job);
    ASSERT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
    float rgb[6];
    ASSERT_EQ(bakegi_job_get_result(job, rgb, 2), BAKEGI_OK);
    size_t length = 0;
    ASSERT_EQ(bakegi_job_get_report(job, nullptr, 0, &length), BAKEGI_OK);
    std::string report(length + 1, '\0');
    ASSERT_EQ(bakegi_job_get_report(job, report.data(), report.size(), &length), BAKEGI_OK);
    EXPECT_NE(report.find("\"antiradiance_off_surface_points\": 1"), std::string::npos) << report;
    EXPECT_GT(rgb[1], 0.0f);  // the floor inside is lit indirectly
    if (rays > 0) {
      EXPECT_EQ(rgb[4], 0.0f) << "a point in open space got light";
      EXPECT_EQ(report.find("lie off every surface"), std::string::npos);
    } else {
      EXPECT_NE(report.find("lie off every surface"), std::string::npos) << report;
    }
  }
}

}  // namespace
}  // namespace bakegi::test
