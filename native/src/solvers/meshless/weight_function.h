// The meshless basis' weight functions and the placement distance (Lehtinen et al. 2008,
// §2.2 Eqs. 8-10 and §2.3 Eq. 11). Shared by the basis (evaluation), the point placement
// (Poisson-disk test) and the transfer (Eq. 16 evaluates B_j at ray hits).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace bakegi::meshless {

// F_squash of Eq. 10: the support's extent along the normal is 1/(1 + F_squash) of its
// tangential extent, so a basis function reaches little past a surface's own plane.
inline constexpr float kSquash = 2.0f;

// One point of the hierarchy, p_j = (x_j, n_j) with support radius r_j on level `level`
// (0 = coarsest).
struct BasisPoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // unit
  float radius = 0.0f;                 // r_j = C R_level
  uint32_t level = 0;
};

// Eq. 9: K(r) = 2r^3 - 3r^2 + 1 on [0, 1], 0 beyond; C1 at both ends.
inline float kernel(float r) {
  if (r >= 1.0f) return 0.0f;
  return (2.0f * r - 3.0f) * r * r + 1.0f;
}

// Eq. 10: ||x - x_j + F_squash <x - x_j, n_j> n_j|| (a Mahalanobis distance whose iso-
// surfaces are ellipsoids flattened along n_j).
inline float squashed_distance(const BasisPoint& point, const glm::vec3& x) {
  const glm::vec3 d = x - point.position;
  return glm::length(d + kSquash * glm::dot(d, point.normal) * point.normal);
}

// Eq. 8: w_j(x, n) = K(dist_j(x) / r_j) max(0, n . n_j)^2. Zero for back-facing normals.
inline float weight(const BasisPoint& point, const glm::vec3& x, const glm::vec3& n) {
  const float facing = glm::dot(n, point.normal);
  if (facing <= 0.0f) return 0.0f;
  return kernel(squashed_distance(point, x) / point.radius) * facing * facing;
}

// Eq. 11: D(p, q) = min(dist_p(x_q), dist_q(x_p)) / max(0, n_p . n_q)^2, infinite for
// normals 90 degrees or more apart. D >= |x_p - x_q| always (the squash only lengthens the
// normal component and the cosine factor is at most 1), so a Euclidean search of radius R
// finds every point within D < R.
inline float poisson_distance(const BasisPoint& p, const BasisPoint& q) {
  const float facing = glm::dot(p.normal, q.normal);
  if (facing <= 0.0f) return std::numeric_limits<float>::infinity();
  const float distance =
      std::min(squashed_distance(p, q.position), squashed_distance(q, p.position));
  return distance / (facing * facing);
}

}  // namespace bakegi::meshless
