#include "solvers/pathtrace/indirect_path.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "lights/direct_light.h"
#include "scene/surface_bsdf.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Roulette starts after this many reflecting vertices: early bounces carry most of the
// light and would only gain variance from it.
constexpr int kRouletteStartBounce = 3;
// Survival probability sqrt(max throughput), as in Cycles: milder than the throughput
// itself, which measured 1.4x (albedo 0.7) to 5x (albedo 0.3) less efficient (variance x
// rays) in the closed sphere of test_pathtrace_sphere.cpp.
float survival_probability(const glm::vec3& throughput) {
  return std::min(1.0f, std::sqrt(max_component(throughput)));
}

struct DirectionSample {
  glm::vec3 direction;
  float pdf;
};

DirectionSample sample_cosine(const SurfacePoint& x, RandomStream& rng) {
  const float u1 = rng.next_float(), u2 = rng.next_float();
  const glm::vec3 local = sample_cosine_hemisphere(u1, u2);
  return {Frame(x.shading_normal).to_world(local), local.z * kInvPi};
}

}  // namespace

FirstRay sample_first_ray(const DirectLight& direct, const SurfacePoint& point, RandomStream& rng) {
  const DirectionSample first = sample_cosine(point, rng);
  return {direct.ray_origin(point), first.direction, first.pdf};
}

PathRadiance trace_from_first_hit(const DirectLight& direct, const Hit& first_hit,
                                  const glm::vec3& first_direction, RandomStream& rng,
                                  int max_bounces, uint64_t& rays,
                                  const PathContinuation* continuation) {
  const Scene& scene = direct.scene();
  const RayTracer& tracer = direct.tracer();
  PathRadiance result;
  Hit hit = first_hit;
  glm::vec3 direction = first_direction;
  // The first vertex's light sample goes to result.first_light, the rest here, scaled by
  // the continuation's weight.
  glm::vec3 radiance(0.0f);
  glm::vec3 throughput(1.0f);
  for (int bounce = 1; hit.hit; ++bounce) {
    const SurfacePoint x = surface_at_hit(scene, hit, direction);
    const glm::vec3 albedo = scene.albedo_at(hit.triangle, hit.b1, hit.b2);
    const Material& material = scene.material_of(hit.triangle);

    // Light sampling (next-event estimation).
    std::optional<SurfaceBsdf> bsdf;
    if (!material.has_glossy()) {
      // Diffuse fast path: rho / pi * E_light.
      if (!(max_component(albedo) > 0.0f)) break;
      radiance += throughput * albedo * (kInvPi * direct.sample_lights(x, rng, rays));
    } else {
      // Diffuse + Phong: the same two strategies with the mixture's f cos and density.
      bsdf.emplace(x.shading_normal, -direction, albedo, material.glossy, material.glossy_exponent);
      radiance += throughput * direct.sample_lights(x, *bsdf, rng, rays);
    }
    if (bounce == 1) {
      result.first_light = radiance;
      radiance = glm::vec3(0.0f);
      result.rest_weight = continuation ? continuation->weight_of_rest(rng) : 1.0f;
      if (!(result.rest_weight > 0.0f)) return result;
      throughput *= result.rest_weight;
    }
    // BSDF sampling.
    DirectionSample next;
    if (!bsdf) {
      // rho / pi * (pi L) per cosine-weighted sample.
      next = sample_cosine(x, rng);
      if (!(next.pdf > 0.0f) || glm::dot(next.direction, x.geometric_normal) <= 0.0f) break;
      throughput *= albedo;
    } else {
      const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
      const BsdfSample sampled = bsdf->sample(u0, u1, u2);
      if (!(sampled.pdf > 0.0f) || glm::dot(sampled.direction, x.geometric_normal) <= 0.0f) {
        break;
      }
      next = {sampled.direction, sampled.pdf};
      throughput *= sampled.weight;
      if (!(max_component(throughput) > 0.0f)) break;
    }
    const glm::vec3 origin = direct.ray_origin(x);
    direction = next.direction;
    ++rays;
    hit = tracer.intersect(Ray{origin, direction, 0.0f, 1e30f});
    radiance += throughput * direct.emission_along(x.position, direction, hit, next.pdf);

    if (bounce >= max_bounces) break;
    if (bounce >= kRouletteStartBounce) {
      const float survival = survival_probability(throughput);
      if (rng.next_float() >= survival) break;
      throughput /= survival;
    }
  }
  result.rest = radiance;
  return result;
}

glm::vec3 sample_indirect(const DirectLight& direct, const SurfacePoint& point, RandomStream& rng,
                          int max_bounces, uint64_t& rays) {
  const FirstRay first = sample_first_ray(direct, point, rng);
  if (!(first.pdf > 0.0f)) return glm::vec3(0.0f);
  ++rays;
  const Hit hit = direct.tracer().intersect(Ray{first.origin, first.direction, 0.0f, 1e30f});
  const PathRadiance path =
      trace_from_first_hit(direct, hit, first.direction, rng, max_bounces, rays);
  return path.first_light + path.rest;
}

}  // namespace bakegi
