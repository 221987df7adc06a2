// What light sampling and light intersection hand back to direct lighting and MIS.
#pragma once

#include <glm/glm.hpp>

namespace bakegi {

// A direction towards a light chosen by that light's sampling strategy, seen from a
// shading point.
struct LightSample {
  glm::vec3 direction{0.0f};  // unit, from the shading point towards the light
  float distance = 0.0f;      // to the sampled point; infinity for the sun
  // Emitted radiance over the solid-angle density of the sample (for delta lights:
  // intensity / distance^2): irradiance contributed per unit of receiver cosine.
  glm::vec3 contribution{0.0f};
  float pdf = 0.0f;          // solid-angle density of the strategy, 0 for delta lights (no MIS)
  bool casts_shadow = true;  // false: no shadow ray (a light with BAKEGI_LIGHT_NO_SHADOW)
  uint32_t seed = 0;         // the shadow ray's Ray::seed: from the sample's random numbers
};

// A ray that crossed a light shape which is not a triangle of the BVH.
struct LightHit {
  float distance = 0.0f;
  glm::vec3 radiance{0.0f};  // emitted towards the ray origin
  float pdf = 0.0f;          // solid-angle density of the light's sampling strategy
};

}  // namespace bakegi
