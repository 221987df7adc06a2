// The geometry of one triangle given by its three corners (counter-clockwise), in the
// barycentric coordinates (b1, b2) of corners 1 and 2 that the whole core uses (Embree's hit
// barycentrics, Scene::albedo_at): corner 0 at (0, 0), corner 1 at (1, 0), corner 2 at (0, 1).
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace bakegi {

// What the corners hold (positions, shading normals, uvs) at barycentrics b, linearly.
template <typename V>
V at_barycentrics(const V (&corner)[3], glm::vec2 b) {
  return (1.0f - b.x - b.y) * corner[0] + b.x * corner[1] + b.y * corner[2];
}

// Barycentrics (b1, b2) of p, by least squares in the triangle's plane (p off the plane is
// projected onto it); (1/3, 1/3) for a degenerate triangle.
inline glm::vec2 barycentrics_of(const glm::vec3 (&corner)[3], const glm::vec3& p) {
  const glm::vec3 e1 = corner[1] - corner[0], e2 = corner[2] - corner[0], d = p - corner[0];
  const float a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2);
  const float r1 = glm::dot(d, e1), r2 = glm::dot(d, e2);
  const float det = a * c - b * b;
  if (!(std::abs(det) > 0.0f)) return glm::vec2(1.0f / 3.0f);
  return glm::vec2((c * r1 - b * r2) / det, (a * r2 - b * r1) / det);
}

// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection, 5.1.5), in
// float (glm::vec3) or double (glm::dvec3).
template <typename V>
V closest_point_on_triangle(const V& p, const V& a, const V& b, const V& c) {
  using T = typename V::value_type;
  const V ab = b - a, ac = c - a, ap = p - a;
  const T d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= T(0) && d2 <= T(0)) return a;
  const V bp = p - b;
  const T d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= T(0) && d4 <= d3) return b;
  const T vc = d1 * d4 - d3 * d2;
  if (vc <= T(0) && d1 >= T(0) && d3 <= T(0)) return a + ab * (d1 / (d1 - d3));
  const V cp = p - c;
  const T d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= T(0) && d5 <= d6) return c;
  const T vb = d5 * d2 - d1 * d6;
  if (vb <= T(0) && d2 >= T(0) && d6 <= T(0)) return a + ac * (d2 / (d2 - d6));
  const T va = d3 * d6 - d5 * d4;
  if (va <= T(0) && (d4 - d3) >= T(0) && (d5 - d6) >= T(0)) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const T denominator = T(1) / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

}  // namespace bakegi
