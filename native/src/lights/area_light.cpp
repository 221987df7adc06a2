#include "lights/area_light.h"

#include <algorithm>
#include <cmath>

#include "lights/spherical_rectangle.h"
#include "util/sampling.h"

namespace bakegi {

AreaLight::AreaLight(const Light& light)
    : casts_shadow_(!(light.flags & BAKEGI_LIGHT_NO_SHADOW)),
      center_(light.position),
      normal_(glm::normalize(light.direction)),
      radiance_(light.color) {
  // Orthonormalize axis_u against the normal; fall back to any tangent if they are parallel.
  glm::vec3 u = light.axis_u - normal_ * glm::dot(light.axis_u, normal_);
  const float u_length = glm::length(u);
  axis_u_ = u_length > 1e-6f ? u / u_length : Frame(normal_).tangent;
  axis_v_ = glm::cross(normal_, axis_u_);
  const bool uniform = light.shape == BAKEGI_AREA_SQUARE || light.shape == BAKEGI_AREA_DISK;
  round_ = light.shape == BAKEGI_AREA_DISK || light.shape == BAKEGI_AREA_ELLIPSE;
  half_u_ = 0.5f * light.size_x;
  half_v_ = 0.5f * (uniform ? light.size_x : light.size_y);
  area_ = round_ ? kPi * half_u_ * half_v_ : 4.0f * half_u_ * half_v_;
  const float half_spread = 0.5f * light.spot_size;
  if (half_spread > 0.0f && half_spread < 0.5f * kPi - 1e-4f) {
    tan_half_spread_ = std::tan(half_spread);
    // tan h - h loses its digits for small h: its series h^3 / 3 there (as Cycles does).
    normalize_spread_ = half_spread > 0.05f ? 1.0f / (tan_half_spread_ - half_spread)
                                            : 3.0f / (half_spread * half_spread * half_spread);
  }
  if (!round_) {
    rectangle_ = SphericalRectangle::Shape(
        glm::dvec3(center_ - axis_u_ * half_u_ - axis_v_ * half_v_),
        glm::dvec3(axis_u_ * (2.0f * half_u_)), glm::dvec3(axis_v_ * (2.0f * half_v_)));
  }
}

glm::vec3 AreaLight::point_at(float u1, float u2) const {
  const glm::vec2 local =
      round_ ? sample_concentric_disk(u1, u2) * glm::vec2(half_u_, half_v_)
             : glm::vec2((2.0f * u1 - 1.0f) * half_u_, (2.0f * u2 - 1.0f) * half_v_);
  return center_ + axis_u_ * local.x + axis_v_ * local.y;
}

float AreaLight::spread_attenuation(float cos_light) const {
  if (normalize_spread_ == 0.0f) return 1.0f;
  const float tan_a = std::sqrt(std::max(0.0f, 1.0f - cos_light * cos_light)) / cos_light;
  return std::max((tan_half_spread_ - tan_a) * normalize_spread_, 0.0f);
}

bool AreaLight::sample(const glm::vec3& p, float u1, float u2, LightSample& out) const {
  if (glm::dot(p - center_, normal_) <= 0.0f || !(area_ > 0.0f)) return false;
  glm::vec3 q;
  float solid_angle = 0.0f;
  if (round_) {
    const glm::vec2 local = sample_concentric_disk(u1, u2) * glm::vec2(half_u_, half_v_);
    q = center_ + axis_u_ * local.x + axis_v_ * local.y;
  } else {
    const SphericalRectangle rectangle = spherical_rectangle(p);
    solid_angle = float(rectangle.solid_angle());
    if (!(solid_angle > 0.0f)) return false;
    q = glm::vec3(rectangle.sample(u1, u2));
  }
  const glm::vec3 to_q = q - p;
  const float distance = glm::length(to_q);
  if (!(distance > 0.0f)) return false;
  out.direction = to_q / distance;
  const float cos_light = -glm::dot(normal_, out.direction);
  if (cos_light <= 0.0f) return false;
  const float spread = spread_attenuation(cos_light);
  if (!(spread > 0.0f)) return false;
  out.distance = distance;
  out.pdf = round_ ? distance * distance / (area_ * cos_light) : 1.0f / solid_angle;
  out.contribution = radiance_ * (spread / out.pdf);
  return true;
}

bool AreaLight::intersect(const glm::vec3& origin, const glm::vec3& direction, float t_max,
                          LightHit& out) const {
  const float cos_light = -glm::dot(direction, normal_);
  if (cos_light <= 0.0f || !(area_ > 0.0f)) return false;  // one-sided
  const float t = glm::dot(origin - center_, normal_) / cos_light;
  if (!(t > 0.0f && t < t_max)) return false;
  const glm::vec3 offset = origin + direction * t - center_;
  const float x = glm::dot(offset, axis_u_) / half_u_;
  const float y = glm::dot(offset, axis_v_) / half_v_;
  const bool inside = round_ ? x * x + y * y <= 1.0f : std::abs(x) <= 1.0f && std::abs(y) <= 1.0f;
  if (!inside) return false;
  const float spread = spread_attenuation(cos_light);
  if (!(spread > 0.0f)) return false;
  out.distance = t;
  out.radiance = radiance_ * spread;
  out.pdf =
      round_ ? t * t / (area_ * cos_light) : float(1.0 / spherical_rectangle(origin).solid_angle());
  return true;
}

}  // namespace bakegi
