#include "lights/spot_light.h"

#include <cmath>

namespace bakegi {

SpotCone::SpotCone(const Light& light)
    : enabled_(true),
      axis_(glm::normalize(light.direction)),
      cos_half_angle_(std::cos(0.5f * light.spot_size)),
      smooth_((1.0f - std::cos(0.5f * light.spot_size)) * light.spot_blend),
      cosine_((light.flags & BAKEGI_LIGHT_SPOT_WITHOUT_COSINE) == 0) {}

float SpotCone::attenuation(const glm::vec3& direction) const {
  if (!enabled_) return 1.0f;
  const float a = glm::dot(axis_, direction);
  if (a <= cos_half_angle_) return 0.0f;
  const float t = a - cos_half_angle_;
  const float falloff = cosine_ ? a : 1.0f;
  if (smooth_ > 0.0f && t < smooth_) {
    const float x = t / smooth_;
    return falloff * x * x * (3.0f - 2.0f * x);
  }
  return falloff;
}

}  // namespace bakegi
