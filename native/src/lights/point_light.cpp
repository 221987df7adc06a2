#include "lights/point_light.h"

#include <cmath>

#include "util/sampling.h"

namespace bakegi {

PointLight::PointLight(const Light& light)
    : casts_shadow_(!(light.flags & BAKEGI_LIGHT_NO_SHADOW)),
      center_(light.position),
      radius_(light.radius),
      intensity_(light.color),
      cone_(light.type == BAKEGI_LIGHT_SPOT ? SpotCone(light) : SpotCone()) {}

bool PointLight::sample(const glm::vec3& p, float u1, float u2, LightSample& out) const {
  const glm::vec3 to_p = p - center_;
  const float center_distance = glm::length(to_p);
  if (!(center_distance > 0.0f)) return false;
  if (is_delta()) {
    const glm::vec3 from_light = to_p / center_distance;
    const float attenuation = cone_.attenuation(from_light);
    if (attenuation <= 0.0f) return false;
    out.direction = -from_light;
    out.distance = center_distance;
    out.contribution = intensity_ * (attenuation / (center_distance * center_distance));
    out.pdf = 0.0f;
    return true;
  }
  // Uniform on the disk facing p, converted to solid angle at p.
  const glm::vec3 disk_normal = to_p / center_distance;
  const glm::vec2 d = sample_concentric_disk(u1, u2) * radius_;
  const Frame frame(disk_normal);
  const glm::vec3 q = center_ + frame.tangent * d.x + frame.bitangent * d.y;
  const glm::vec3 to_q = q - p;
  const float distance = glm::length(to_q);
  if (!(distance > 0.0f)) return false;
  const glm::vec3 direction = to_q / distance;
  const float cos_light = -glm::dot(disk_normal, direction);
  if (cos_light <= 0.0f) return false;
  const float attenuation = cone_.attenuation(-direction);
  if (attenuation <= 0.0f) return false;
  const float area = kPi * radius_ * radius_;
  out.direction = direction;
  out.distance = distance;
  out.pdf = distance * distance / (area * cos_light);
  out.contribution = intensity_ * (attenuation / area / out.pdf);
  return true;
}

bool PointLight::intersect(const glm::vec3& origin, const glm::vec3& direction, float t_max,
                           LightHit& out) const {
  if (is_delta()) return false;
  const glm::vec3 to_origin = origin - center_;
  const float center_distance = glm::length(to_origin);
  if (!(center_distance > 0.0f)) return false;
  const glm::vec3 disk_normal = to_origin / center_distance;
  const float cos_light = -glm::dot(direction, disk_normal);
  if (cos_light <= 0.0f) return false;
  const float t = center_distance / cos_light;  // plane through the center, facing the origin
  if (!(t > 0.0f && t < t_max)) return false;
  const glm::vec3 h = origin + direction * t;
  const glm::vec3 offset = h - center_;
  if (glm::dot(offset, offset) > radius_ * radius_) return false;
  const float attenuation = cone_.attenuation(-direction);
  if (attenuation <= 0.0f) return false;
  const float area = kPi * radius_ * radius_;
  out.distance = t;
  out.radiance = intensity_ * (attenuation / area);
  out.pdf = t * t / (area * cos_light);
  return true;
}

}  // namespace bakegi
