// Warps from uniform numbers in [0,1)^2 to the domains light transport integrates over,
// and the orthonormal frames they are expressed in.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace bakegi {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.31830988618379067154f;

// A right-handed orthonormal basis around a unit normal (Duff et al. 2017, branchless).
struct Frame {
  glm::vec3 tangent, bitangent, normal;

  explicit Frame(const glm::vec3& n) : normal(n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    tangent = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    bitangent = glm::vec3(b, sign + n.y * n.y * a, -n.y);
  }

  glm::vec3 to_world(const glm::vec3& local) const {
    return tangent * local.x + bitangent * local.y + normal * local.z;
  }
};

// Uniform on the unit disk, Shirley and Chiu's concentric map (keeps strata compact).
inline glm::vec2 sample_concentric_disk(float u1, float u2) {
  const float a = 2.0f * u1 - 1.0f;
  const float b = 2.0f * u2 - 1.0f;
  if (a == 0.0f && b == 0.0f) return glm::vec2(0.0f);
  float r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = (kPi / 4.0f) * (b / a);
  } else {
    r = b;
    phi = (kPi / 2.0f) - (kPi / 4.0f) * (a / b);
  }
  return glm::vec2(r * std::cos(phi), r * std::sin(phi));
}

// Cosine-weighted direction around +z (Malley's method); density cos(theta) / pi.
inline glm::vec3 sample_cosine_hemisphere(float u1, float u2) {
  const glm::vec2 d = sample_concentric_disk(u1, u2);
  const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return glm::vec3(d.x, d.y, z);
}

// Uniform on a triangle: barycentrics (b1, b2) of corners 1 and 2.
inline glm::vec2 sample_triangle_barycentrics(float u1, float u2) {
  const float s = std::sqrt(u1);
  return glm::vec2(u2 * s, 1.0f - s);
}

// Power heuristic (beta = 2) weight of a strategy with density `pdf` against `other_pdf`.
inline float power_heuristic(float pdf, float other_pdf) {
  if (std::isinf(pdf)) return 1.0f;
  const float a = pdf * pdf;
  const float b = other_pdf * other_pdf;
  if (std::isinf(b)) return 0.0f;
  return a > 0.0f ? a / (a + b) : 0.0f;
}

inline float max_component(const glm::vec3& v) {
  return std::max(v.x, std::max(v.y, v.z));
}

// No component NaN or infinite (a Monte Carlo sample that is not is dropped and reported).
inline bool is_finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace bakegi
