#include "lights/surface_point.h"

namespace bakegi {

SurfacePoint surface_at_hit(const Scene& scene, const Hit& hit, const glm::vec3& ray_direction) {
  const Triangle& t = scene.triangles[hit.triangle];
  const float b0 = 1.0f - hit.b1 - hit.b2;
  SurfacePoint x;
  x.position = t.p[0] * b0 + t.p[1] * hit.b1 + t.p[2] * hit.b2;
  x.geometric_normal =
      glm::dot(t.face_normal, ray_direction) > 0.0f ? -t.face_normal : t.face_normal;
  const glm::vec3 interpolated = t.n[0] * b0 + t.n[1] * hit.b1 + t.n[2] * hit.b2;
  const float length = glm::length(interpolated);
  glm::vec3 shading = length > 1e-12f ? interpolated / length : x.geometric_normal;
  if (glm::dot(shading, x.geometric_normal) < 0.0f) shading = -shading;
  x.shading_normal = shading;
  return x;
}

}  // namespace bakegi
