#include "solvers/splatting/near_field_gather.h"

#include <algorithm>
#include <cmath>

#include "lights/direct_light.h"
#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

float geometry_bound(const VirtualPointLights& vpls, float radii) {
  double area = 0.0;  // sum of A / pi
  for (float a : vpls.disk_areas) area += a;
  if (vpls.size() == 0 || !(area > 0.0)) return 0.0f;
  const double d2 = double(radii) * double(radii) * area / double(vpls.size());
  return float(1.0 / d2);
}

glm::vec3 clamped_vpl_light(const VirtualPointLights& vpls, const glm::vec3& position,
                            const glm::vec3& normal, size_t begin, size_t end, float bound) {
  return sum_over_vpls(vpls, position, normal, begin, end,
                       [bound](float r2, float cr, float cv, float) {
                         return r2 > 0.0f ? std::min(cr * cv / (r2 * r2), bound) : 0.0f;
                       });
}

glm::vec3 near_field_residual(const Scene& scene, const RayTracer& tracer,
                              const DirectLight& direct, const glm::vec3& position,
                              const glm::vec3& normal, float bound, uint32_t rays, uint64_t seed,
                              uint64_t point, uint64_t& traced) {
  if (rays == 0 || !(bound > 0.0f)) return glm::vec3(0.0f);
  const Frame frame(normal);
  const SurfacePoint x{position, normal, normal};
  glm::vec3 sum(0.0f);
  for (uint32_t k = 0; k < rays; ++k) {
    RandomStream rng(sample_pcg(seed ^ 0x5eed5eedull, point, k));
    const glm::vec3 local = sample_cosine_hemisphere(rng.next_float(), rng.next_float());
    Ray ray;
    ray.origin = direct.ray_origin(x);
    ray.direction = frame.to_world(local);
    const Hit hit = tracer.intersect(ray);
    ++traced;
    if (!hit.hit) continue;
    const SurfacePoint y = surface_at_hit(scene, hit, ray.direction);
    const float cos_y = std::max(0.0f, -glm::dot(ray.direction, y.shading_normal));
    const float g = local.z * cos_y / (hit.t * hit.t);
    if (!(g > bound)) continue;
    const Triangle& triangle = scene.triangles[hit.triangle];
    // The light leaving y towards x: its direct light reflected diffusely (E albedo / pi).
    const glm::vec3 reflected = scene.albedo_at(triangle, hit.b1, hit.b2) *
                                direct.irradiance_sample(y, rng, traced) * kInvPi;
    sum += reflected * (1.0f - bound / g);
  }
  return sum / float(rays);
}

}  // namespace bakegi
