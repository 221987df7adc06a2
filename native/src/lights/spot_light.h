// The cone of a spot light, as Cycles 3.4.1 evaluates it (kernel/light/light.h,
// spot_light_attenuation): with a = dot(axis, direction from the light to the point),
//   a <= cos(spot_size / 2)            -> 0
//   t = a - cos_half < smooth          -> a * smoothstep(t / smooth)
//   otherwise                          -> a
// where smooth = (1 - cos_half) * spot_blend. The result is multiplied by `a` itself, so
// the intensity inside the cone falls off as the cosine to the axis (intensity I on the
// axis, not concentrated by the cone). Cycles 4.0 dropped that factor (kernel/light/spot.h:
// smoothstep alone); a light with BAKEGI_LIGHT_SPOT_WITHOUT_COSINE is evaluated that way.
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace bakegi {

class SpotCone {
 public:
  SpotCone() = default;  // no cone: attenuation 1 everywhere (a point light)
  explicit SpotCone(const Light& light);

  // direction: unit vector from the light towards the lit point.
  float attenuation(const glm::vec3& direction) const;

 private:
  bool enabled_ = false;
  glm::vec3 axis_{0.0f, 0.0f, -1.0f};
  float cos_half_angle_ = -1.0f;
  float smooth_ = 0.0f;
  bool cosine_ = true;  // Cycles 3.x: times a
};

}  // namespace bakegi
