#include "solvers/antiradiance/near_field_gather.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lights/direct_light.h"
#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::antiradiance {

NearFieldGather::NearFieldGather(const DirectLight& direct,
                                 std::shared_ptr<const PatchRadianceCache> cache,
                                 const NearFieldSettings& settings)
    : direct_(&direct), cache_(std::move(cache)), settings_(settings) {}

NearFieldGather::Gathered NearFieldGather::gather(const glm::vec3& position,
                                                  const glm::vec3& normal, uint64_t point,
                                                  uint64_t& rays_cast) const {
  const Scene& scene = direct_->scene();
  const RayTracer& tracer = direct_->tracer();
  const uint32_t rays = settings_.rays;
  const uint32_t side = static_cast<uint32_t>(std::sqrt(static_cast<double>(rays)));
  const uint32_t stratified = side * side;
  const Frame frame(normal);
  const glm::vec3 origin = position + normal * settings_.ray_epsilon;
  RandomStream rng = sample_stream(settings_.seed, point, 0);
  Gathered g;
  g.nearest = std::numeric_limits<float>::infinity();
  for (uint32_t r = 0; r < rays; ++r) {
    float u1 = rng.next_float(), u2 = rng.next_float();
    if (r < stratified) {
      u1 = (static_cast<float>(r % side) + u1) / static_cast<float>(side);
      u2 = (static_cast<float>(r / side) + u2) / static_cast<float>(side);
    }
    const glm::vec3 local = sample_cosine_hemisphere(u1, u2);
    const glm::vec3 direction = frame.to_world(local);
    const Hit hit = tracer.intersect(Ray{origin, direction});
    ++rays_cast;
    if (!hit.hit) continue;
    g.nearest = std::min(g.nearest, hit.t);
    CachedIrradiance cached;
    if (!cache_->irradiance_at(hit, direction, cached)) {
      ++g.unseen;
      continue;
    }
    const Triangle& triangle = scene.triangles[hit.triangle];
    const glm::vec3 albedo = scene.albedo_at(triangle, hit.b1, hit.b2);
    if (albedo.x <= 0.0f && albedo.y <= 0.0f && albedo.z <= 0.0f) continue;
    const SurfacePoint y = surface_at_hit(scene, hit, direction);
    const glm::vec3 direct = direct_->irradiance_sample(y, rng, rays_cast);
    g.sum += glm::dvec3(albedo * (direct * kInvPi + cached.indirect_over_pi));
  }
  return g;
}

bool NearFieldGather::gather_off_surface(const glm::vec3& position, const glm::vec3& normal,
                                         uint64_t point, glm::vec3& value,
                                         uint64_t& rays_cast) const {
  if (!enabled() || !cache_) return false;
  const Gathered g = gather(position, normal, point, rays_cast);
  value = glm::vec3(g.sum / static_cast<double>(settings_.rays));
  return true;
}

glm::vec3 NearFieldGather::evaluate(const glm::vec3& position, const glm::vec3& normal,
                                    uint64_t point, const glm::vec3& splat,
                                    uint64_t& rays_cast) const {
  if (!enabled() || !cache_) return splat;
  const RayTracer& tracer = direct_->tracer();
  const uint32_t rays = settings_.rays;
  const Frame frame(normal);
  const glm::vec3 origin = position + normal * settings_.ray_epsilon;
  // Probe first: most bake points are far from other surfaces and keep the splat.
  {
    float nearest = std::numeric_limits<float>::infinity();
    for (uint32_t r = 0; r < kProbeSide * kProbeSide; ++r) {
      const float u1 = (static_cast<float>(r % kProbeSide) + 0.5f) / kProbeSide;
      const float u2 = (static_cast<float>(r / kProbeSide) + 0.5f) / kProbeSide;
      Ray probe{origin, frame.to_world(sample_cosine_hemisphere(u1, u2))};
      probe.tfar = settings_.far;
      const Hit hit = tracer.intersect(probe);
      ++rays_cast;
      if (hit.hit) nearest = std::min(nearest, hit.t);
    }
    if (!(nearest < settings_.far)) return splat;
  }
  const Gathered g = gather(position, normal, point, rays_cast);
  // Mostly the backs of faces: the point lies inside or behind geometry (e.g. a bake point
  // a little off a tessellated curved surface); the gather has nothing to say there.
  if (!(g.nearest < settings_.far) || 2 * g.unseen > rays) return splat;
  const glm::vec3 gathered = glm::vec3(g.sum / static_cast<double>(rays));
  const float nearest = g.nearest;
  const float span = std::max(settings_.far - settings_.near, 1e-12f);
  const float t = std::clamp((settings_.far - nearest) / span, 0.0f, 1.0f);
  const float blend = t * t * (3.0f - 2.0f * t);  // smoothstep: C1 across both ends
  return glm::mix(splat, gathered, blend);
}

}  // namespace bakegi::antiradiance
