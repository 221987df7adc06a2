#include "solvers/antiradiance/coincident_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace bakegi::antiradiance {
namespace {

// Normals agree when their components agree to this (about 0.06 degrees).
constexpr float kNormalQuantum = 1e-3f;
// Planes agree when their offsets agree to this fraction of the scene's extent.
constexpr float kRelativePlaneTolerance = 1e-4f;

struct PlaneKey {
  std::array<int32_t, 3> normal;  // the quantized normal, turned to a canonical sign
  float offset;                   // distance of the plane from the origin along it
  bool flipped;                   // the triangle faces against the canonical normal
};

PlaneKey plane_key(const Triangle& t) {
  glm::vec3 n = t.face_normal;
  // Canonical sign: the first clearly non-zero component positive.
  const int axis = std::abs(n.x) > 1e-6f ? 0 : (std::abs(n.y) > 1e-6f ? 1 : 2);
  const bool flipped = n[axis] < 0.0f;
  if (flipped) n = -n;
  const glm::vec3 centroid = (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
  return {{int32_t(std::lround(n.x / kNormalQuantum)), int32_t(std::lround(n.y / kNormalQuantum)),
           int32_t(std::lround(n.z / kNormalQuantum))},
          glm::dot(n, centroid),
          flipped};
}

// Whether point p (in t's plane, within tolerance) lies inside triangle t.
bool covers(const Triangle& t, const glm::vec3& p) {
  const glm::vec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = p - t.p[0];
  const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const float d1 = glm::dot(d, e1), d2 = glm::dot(d, e2);
  const float det = d11 * d22 - d12 * d12;
  if (!(det > 0.0f)) return false;
  const float b1 = (d22 * d1 - d12 * d2) / det, b2 = (d11 * d2 - d12 * d1) / det;
  constexpr float kSlack = -1e-4f;
  return b1 >= kSlack && b2 >= kSlack && b1 + b2 <= 1.0f - kSlack;
}

}  // namespace

std::vector<uint8_t> backed_by_coincident_face(const Scene& scene) {
  const size_t count = scene.triangles.size();
  std::vector<uint8_t> backed(count, 0);
  std::vector<PlaneKey> keys(count);
  for (size_t i = 0; i < count; ++i) keys[i] = plane_key(scene.triangles[i]);
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (keys[a].normal != keys[b].normal) return keys[a].normal < keys[b].normal;
    return keys[a].offset < keys[b].offset;
  });
  const float tolerance = kRelativePlaneTolerance * std::max(scene.extent(), 1e-3f);
  // Each triangle against the later ones of its normal within `tolerance` of its plane.
  for (size_t a = 0; a < count; ++a) {
    const uint32_t i = order[a];
    const glm::vec3 ci =
        (scene.triangles[i].p[0] + scene.triangles[i].p[1] + scene.triangles[i].p[2]) / 3.0f;
    for (size_t b = a + 1; b < count; ++b) {
      const uint32_t j = order[b];
      if (keys[j].normal != keys[i].normal || keys[j].offset - keys[i].offset > tolerance) break;
      if (keys[j].flipped == keys[i].flipped) continue;
      const glm::vec3 cj =
          (scene.triangles[j].p[0] + scene.triangles[j].p[1] + scene.triangles[j].p[2]) / 3.0f;
      if (covers(scene.triangles[j], ci)) backed[i] = 1;
      if (covers(scene.triangles[i], cj)) backed[j] = 1;
    }
  }
  return backed;
}

}  // namespace bakegi::antiradiance
