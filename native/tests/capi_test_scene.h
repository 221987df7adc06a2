// Helpers for tests that go through the C API: owning wrappers for its handles and a small
// closed box (a room lit by a point light) built with bakegi_scene_add_*.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bakegi/bakegi.h"
#include "bakegi/bakegi_handles.hpp"

namespace bakegi::test {

using ScenePtr = SceneHandle;
using PointsPtr = PointsHandle;
using SettingsPtr = SettingsHandle;
using JobPtr = JobHandle;

inline ScenePtr new_scene() {
  bakegi_scene* scene = nullptr;
  EXPECT_EQ(bakegi_scene_create(&scene), BAKEGI_OK);
  return ScenePtr(scene);
}

// Settings naming `method` (the C API tests bake with the path tracer unless they name
// another; nullptr leaves the core's default method).
inline SettingsPtr new_settings(const char* method = "pathtrace") {
  bakegi_settings* settings = nullptr;
  EXPECT_EQ(bakegi_settings_create(&settings), BAKEGI_OK);
  if (method) EXPECT_EQ(bakegi_settings_set_string(settings, "method", method), BAKEGI_OK);
  return SettingsPtr(settings);
}

inline bakegi_material_desc grey_material(float albedo = 0.5f) {
  bakegi_material_desc m{};
  m.albedo[0] = m.albedo[1] = m.albedo[2] = albedo;
  m.albedo_texture = BAKEGI_NO_TEXTURE;
  return m;
}

inline bakegi_light_desc point_light(float x, float y, float z, float intensity) {
  bakegi_light_desc l{};
  l.type = BAKEGI_LIGHT_POINT;
  l.position[0] = x, l.position[1] = y, l.position[2] = z;
  l.color[0] = l.color[1] = l.color[2] = intensity;
  return l;
}

// The cube [0,1]^3 as 12 triangles wound so that face normals point inwards.
struct BoxMesh {
  std::vector<float> positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                  0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3,   // floor z=0, normal +z
                                   4, 6, 5, 4, 7, 6,   // ceiling z=1, normal -z
                                   0, 4, 5, 0, 5, 1,   // y=0, normal +y
                                   3, 2, 6, 3, 6, 7,   // y=1, normal -y
                                   0, 3, 7, 0, 7, 4,   // x=0, normal +x
                                   1, 5, 6, 1, 6, 2};  // x=1, normal -x
  bakegi_mesh_desc desc(uint32_t material = 0, uint32_t object_id = 0) const {
    bakegi_mesh_desc d{};
    d.positions = positions.data();
    d.vertex_count = uint32_t(positions.size() / 3);
    d.indices = indices.data();
    d.triangle_count = uint32_t(indices.size() / 3);
    d.material = material;
    d.object_id = object_id;
    return d;
  }
};

// A unit box of albedo 0.5 lit by a point light of 1 W/sr at its centre.
inline ScenePtr new_box_scene() {
  ScenePtr scene = new_scene();
  const bakegi_material_desc material = grey_material();
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &material, nullptr), BAKEGI_OK);
  const BoxMesh box;
  const bakegi_mesh_desc mesh = box.desc();
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  const bakegi_light_desc light = point_light(0.5f, 0.5f, 0.5f, 1.0f);
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &light, nullptr), BAKEGI_OK);
  return scene;
}

// `count` points on the box floor (z = 0, normal +z), spread over a grid.
inline PointsPtr new_floor_points(size_t count) {
  std::vector<float> positions, normals;
  const size_t side = size_t(std::ceil(std::sqrt(double(count))));
  for (size_t i = 0; i < count; ++i) {
    positions.insert(positions.end(),
                     {float((i % side) + 0.5f) / side, float((i / side) + 0.5f) / side, 0.0f});
    normals.insert(normals.end(), {0.0f, 0.0f, 1.0f});
  }
  bakegi_points* points = nullptr;
  EXPECT_EQ(bakegi_points_create(positions.data(), normals.data(), nullptr, count, &points),
            BAKEGI_OK);
  return PointsPtr(points);
}

// Starts a pathtrace job of 2^24 samples per point on the box scene: hours of work, so only
// cancel (or destroy) ends it while a test watches. The caller owns the job.
inline bakegi_job* start_endless_job(size_t point_count) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(point_count);
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 1 << 24), BAKEGI_OK);
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
  return job;  // the job keeps its own copies of scene, points and settings
}

inline std::string last_error() {
  return bakegi_last_error();
}

}  // namespace bakegi::test
