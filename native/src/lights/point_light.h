// Point and spot lights: intensity I (W/sr) from a point or, with a radius r, from a sphere
// that Cycles 3.4 models as a disk of radius r facing the shading point with radiance
// I / (pi r^2) (same far field; soft shadows). Spot lights add a SpotCone.
#pragma once

#include <glm/glm.hpp>

#include "lights/light_sample.h"
#include "lights/spot_light.h"
#include "scene/scene.h"

namespace bakegi {

class PointLight {
 public:
  explicit PointLight(const Light& light);  // BAKEGI_LIGHT_POINT or BAKEGI_LIGHT_SPOT
  // False for a light with Cast Shadow off (BAKEGI_LIGHT_NO_SHADOW).
  bool casts_shadow() const { return casts_shadow_; }

  bool is_delta() const { return radius_ <= 0.0f; }
  // Samples the light seen from p; false if it sends nothing there.
  bool sample(const glm::vec3& p, float u1, float u2, LightSample& out) const;
  // The disk facing the ray origin, if the ray crosses it before t_max (never for r = 0).
  bool intersect(const glm::vec3& origin, const glm::vec3& direction, float t_max,
                 LightHit& out) const;

 private:
  bool casts_shadow_;
  glm::vec3 center_;
  float radius_;
  glm::vec3 intensity_;
  SpotCone cone_;
};

}  // namespace bakegi
