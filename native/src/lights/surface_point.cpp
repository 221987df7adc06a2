#include "lights/surface_point.h"

namespace bakegi {

SurfacePoint surface_at_hit(const Scene& scene, const Hit& hit, const glm::vec3& ray_direction) {
  SurfacePoint x;
  // From the hit, not the Triangle: its load is a cache miss (Hit::position).
  x.position = hit.position;
  const TriangleShading& record = scene.shading[hit.triangle];
  const glm::vec3 face_normal =
      record.sliver ? scene.triangles[hit.triangle].face_normal : glm::normalize(hit.normal);
  x.geometric_normal = glm::dot(face_normal, ray_direction) > 0.0f ? -face_normal : face_normal;
  if (!record.smooth) {
    x.shading_normal = x.geometric_normal;
    return x;
  }
  const Triangle& t = scene.triangles[hit.triangle];
  const float b0 = 1.0f - hit.b1 - hit.b2;
  const glm::vec3 interpolated = t.n[0] * b0 + t.n[1] * hit.b1 + t.n[2] * hit.b2;
  const float length = glm::length(interpolated);
  glm::vec3 shading = length > 1e-12f ? interpolated / length : x.geometric_normal;
  if (glm::dot(shading, x.geometric_normal) < 0.0f) shading = -shading;
  x.shading_normal = shading;
  return x;
}

}  // namespace bakegi
