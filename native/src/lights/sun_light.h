// Sun (distant) light: irradiance S (W/m^2) on a surface facing it, arriving from a disc of
// angular diameter `angle`. As in Cycles 3.4.1 (kernel/light/light.h, LIGHT_DISTANT), the
// disc is a disk of radius tan(angle / 2) at unit distance, sampled uniformly by area: the
// density in solid angle is 1 / (A cos^3 theta) with A = pi tan^2(angle / 2) and theta the
// angle to the sun's centre, and the radiance is S times that density, so every sample
// carries S and a surface facing the sun receives S. angle = 0 is a delta light.
#pragma once

#include <glm/glm.hpp>

#include "lights/light_sample.h"
#include "scene/scene.h"
#include "util/sampling.h"

namespace bakegi {

class SunLight {
 public:
  explicit SunLight(const Light& light);
  // False for a light with Cast Shadow off (BAKEGI_LIGHT_NO_SHADOW).
  bool casts_shadow() const { return casts_shadow_; }

  bool is_delta() const { return disk_area_ <= 0.0f; }
  bool sample(float u1, float u2, LightSample& out) const;
  // Only for rays that leave the scene (the sun is infinitely far).
  bool intersect(const glm::vec3& direction, LightHit& out) const;

 private:
  bool casts_shadow_;
  Frame frame_;  // normal: unit direction towards the sun
  float tan_half_angle_;
  float cos_half_angle_;
  float disk_area_;
  glm::vec3 irradiance_;
};

}  // namespace bakegi
