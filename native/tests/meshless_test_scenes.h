// Small scenes shared by the meshless tests (test_meshless_*.cpp).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "light_transport_fixtures.h"
#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "solvers/meshless/basis_hierarchy.h"

namespace bakegi::test {

// A closed 2 m room (inward walls) with a 0.6 x 0.6 x 0.8 m block on its floor and a point
// light.
inline SceneDescription room_with_block(glm::vec3 light,
                                        glm::vec3 block_albedo = glm::vec3(0.3f, 0.6f, 0.3f)) {
  SceneDescription d;
  const uint32_t walls = add_material(d, glm::vec3(0.6f, 0.5f, 0.4f));
  const uint32_t block = add_material(d, block_albedo);
  d.meshes.push_back(make_cube(glm::vec3(-1, -1, 0), glm::vec3(1, 1, 2), Facing::kInward, walls));
  d.meshes.push_back(make_cube(glm::vec3(-0.3f, -0.3f, 0.0f), glm::vec3(0.3f, 0.3f, 0.8f),
                               Facing::kOutward, block));
  d.lights.push_back(point_light(light, glm::vec3(10.0f)));
  return d;
}

// A floor with a wall standing on it across x = 0 (thin block, 1 m tall); light on the left.
inline Scene floor_with_wall() {
  SceneDescription d;
  const uint32_t grey = add_material(d, glm::vec3(0.5f));
  add_quad(d, glm::vec3(0.0f), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), 3.0f, 3.0f, grey);
  d.meshes.push_back(make_cube(glm::vec3(-0.02f, -3.0f, 0.0f), glm::vec3(0.02f, 3.0f, 1.0f),
                               Facing::kOutward, grey));
  d.lights.push_back(point_light(glm::vec3(-1.0f, 0.0f, 2.0f), glm::vec3(1.0f)));
  return build_scene(d);
}

// A basis point on that floor (y = 0, normal up).
inline meshless::BasisPoint floor_point(float x, float radius, uint32_t level) {
  meshless::BasisPoint p;
  p.position = glm::vec3(x, 0.0f, 0.0f);
  p.normal = glm::vec3(0, 0, 1);
  p.radius = radius;
  p.level = level;
  return p;
}

// One sender function facing down from height z with a support that covers any plate there
// (Shepard with a single point: 1 everywhere it reaches).
inline meshless::BasisHierarchy single_sender_facing_down(float z) {
  meshless::BasisPoint sender;
  sender.position = glm::vec3(0.0f, 0.0f, z);
  sender.normal = glm::vec3(0.0f, 0.0f, -1.0f);
  sender.radius = 10.0f;
  return meshless::BasisHierarchy({sender});
}

}  // namespace bakegi::test
