#include "lights/sun_light.h"

#include <cmath>
#include <limits>

namespace bakegi {

SunLight::SunLight(const Light& light)
    : casts_shadow_(!(light.flags & BAKEGI_LIGHT_NO_SHADOW)),
      frame_(-glm::normalize(light.direction)),
      tan_half_angle_(std::tan(0.5f * light.angle)),
      cos_half_angle_(std::cos(0.5f * light.angle)),
      disk_area_(kPi * tan_half_angle_ * tan_half_angle_),
      irradiance_(light.color) {}

bool SunLight::sample(float u1, float u2, LightSample& out) const {
  out.distance = std::numeric_limits<float>::infinity();
  out.contribution = irradiance_;
  if (is_delta()) {
    out.direction = frame_.normal;
    out.pdf = 0.0f;
    return true;
  }
  const glm::vec2 d = sample_concentric_disk(u1, u2) * tan_half_angle_;
  out.direction = glm::normalize(frame_.to_world(glm::vec3(d.x, d.y, 1.0f)));
  const float cos_theta = glm::dot(out.direction, frame_.normal);
  out.pdf = 1.0f / (disk_area_ * cos_theta * cos_theta * cos_theta);
  return true;
}

bool SunLight::intersect(const glm::vec3& direction, LightHit& out) const {
  if (is_delta()) return false;
  const float cos_theta = glm::dot(direction, frame_.normal);
  if (cos_theta < cos_half_angle_ || cos_theta <= 0.0f) return false;
  out.distance = std::numeric_limits<float>::infinity();
  out.pdf = 1.0f / (disk_area_ * cos_theta * cos_theta * cos_theta);
  out.radiance = irradiance_ * out.pdf;
  return true;
}

}  // namespace bakegi
