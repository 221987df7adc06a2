#include "lights/direct_light.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Relative to the scene size: large enough to leave the surface after float rounding of
// hit points, small against any feature worth baking.
constexpr float kRelativeRayEpsilon = 1e-5f;

float scene_ray_epsilon(const Scene& scene) {
  const glm::vec3 magnitude = glm::max(glm::abs(scene.bounds_min), glm::abs(scene.bounds_max));
  const float scale = std::max({scene.extent(), max_component(magnitude), 1e-3f});
  return kRelativeRayEpsilon * scale;
}

}  // namespace

DirectLight::DirectLight(const Scene& scene, const RayTracer& tracer)
    : scene_(scene),
      tracer_(tracer),
      ray_epsilon_(scene_ray_epsilon(scene)),
      emissive_triangles_(scene),
      world_radiance_(scene.description.world_radiance),
      environment_(scene.environment.get()),
      portals_(scene.description.portals) {
  for (const Light& light : scene.description.lights) {
    switch (light.type) {
      case BAKEGI_LIGHT_POINT:
      case BAKEGI_LIGHT_SPOT:
        point_lights_.emplace_back(light);
        break;
      case BAKEGI_LIGHT_SUN:
        sun_lights_.emplace_back(light);
        break;
      case BAKEGI_LIGHT_AREA:
        area_lights_.emplace_back(light);
        break;
    }
  }
}

template <typename Visit>
void DirectLight::for_each_light_sample(const SurfacePoint& x, RandomStream& rng, World world,
                                        Visit&& visit) const {
  LightSample s;
  for (const PointLight& light : point_lights_) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    s.casts_shadow = light.casts_shadow();
    if (light.sample(x.position, u1, u2, s)) visit(s);
  }
  for (const AreaLight& light : area_lights_) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    s.casts_shadow = light.casts_shadow();
    if (light.sample(x.position, u1, u2, s)) visit(s);
  }
  for (const SunLight& light : sun_lights_) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    s.casts_shadow = light.casts_shadow();
    if (light.sample(u1, u2, s)) visit(s);
  }
  s.casts_shadow = true;  // emissive triangles and the world
  if (!emissive_triangles_.empty()) {
    const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    if (emissive_triangles_.sample(x.position, u0, u1, u2, s)) visit(s);
  }
  // Last, so that scenes without a world image draw the same numbers as before.
  if (world == World::kExcluded) return;
  // Where no portal is seen, exactly as without portals (the same random numbers).
  const float share = portal_share(x.position);
  if (share > 0.0f) {
    if (sample_world_through_portals(x.position, share, rng, s)) visit(s);
  } else if (environment_) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    if (environment_->sample(u1, u2, s)) visit(s);
  }
}

float DirectLight::portal_share(const glm::vec3& x) const {
  if (portals_.empty() || !portals_.seen_from(x)) return 0.0f;
  return environment_ ? 0.5f : 1.0f;
}

float DirectLight::world_pdf(const glm::vec3& x, const glm::vec3& direction, float share) const {
  float pdf = share > 0.0f ? share * portals_.pdf(x, direction) : 0.0f;
  if (environment_) pdf += (1.0f - share) * environment_->pdf(direction);
  return pdf;
}

bool DirectLight::sample_world_through_portals(const glm::vec3& x, float share, RandomStream& rng,
                                               LightSample& out) const {
  const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
  glm::vec3 direction;
  if (u0 < share) {
    float portal_pdf = 0.0f;
    if (!portals_.sample(x, u0 / share, u1, u2, direction, portal_pdf)) return false;
  } else {
    if (!environment_ || !environment_->sample(u1, u2, out)) return false;
    direction = out.direction;
  }
  // The density of the mixture of both strategies, so that either one's sample is weighted
  // against the BSDF's rays as one light.
  const float pdf = world_pdf(x, direction, share);
  if (!(pdf > 0.0f)) return false;
  const glm::vec3 radiance = environment_ ? environment_->radiance(direction) : world_radiance_;
  out.direction = direction;
  out.distance = std::numeric_limits<float>::infinity();
  out.pdf = pdf;
  out.contribution = radiance / pdf;
  return true;
}

bool DirectLight::unoccluded(const SurfacePoint& x, const LightSample& s, uint64_t& rays) const {
  if (!s.casts_shadow) return true;
  // Light geometry is seen from the surface point itself; only the shadow ray starts off
  // the surface, aimed at the sampled point, so the offset adds no bias to 1/d^2.
  const glm::vec3 origin = ray_origin(x);
  Ray shadow{origin, s.direction, 0.0f, 1e30f};
  if (std::isfinite(s.distance)) {
    const glm::vec3 to_light = x.position + s.direction * s.distance - origin;
    const float distance = glm::length(to_light);
    shadow.direction = to_light / distance;
    shadow.tfar = distance - 2.0f * ray_epsilon_;
  }
  ++rays;
  return !tracer_.occluded(shadow);
}

template <typename Visit>
glm::vec3 DirectLight::light_sample_irradiance(const SurfacePoint& x, RandomStream& rng,
                                               uint64_t& rays, World world, Visit&& visit) const {
  glm::vec3 irradiance(0.0f);
  for_each_light_sample(x, rng, world, [&](const LightSample& s) {
    const float cos_receiver = glm::dot(x.shading_normal, s.direction);
    if (cos_receiver <= 0.0f || glm::dot(x.geometric_normal, s.direction) <= 0.0f) return;
    const float weight = s.pdf > 0.0f ? power_heuristic(s.pdf, cos_receiver * kInvPi) : 1.0f;
    if (!(weight > 0.0f) || !unoccluded(x, s, rays)) return;
    const glm::vec3 term = s.contribution * (cos_receiver * weight);
    irradiance += term;
    visit(s.direction, term);
  });
  return irradiance;
}

glm::vec3 DirectLight::sample_lights(const SurfacePoint& x, RandomStream& rng,
                                     uint64_t& rays) const {
  return light_sample_irradiance(x, rng, rays, World::kIncluded,
                                 [](const glm::vec3&, const glm::vec3&) {});
}

glm::vec3 DirectLight::lamp_irradiance(const SurfacePoint& x, RandomStream& rng,
                                       uint64_t& rays) const {
  glm::vec3 irradiance(0.0f);
  for_each_light_sample(x, rng, World::kExcluded, [&](const LightSample& s) {
    const float cos_receiver = glm::dot(x.shading_normal, s.direction);
    if (cos_receiver <= 0.0f || glm::dot(x.geometric_normal, s.direction) <= 0.0f) return;
    if (unoccluded(x, s, rays)) irradiance += s.contribution * cos_receiver;
  });
  return irradiance;
}

glm::vec3 DirectLight::sample_lights(const SurfacePoint& x, const SurfaceBsdf& bsdf,
                                     RandomStream& rng, uint64_t& rays) const {
  glm::vec3 radiance(0.0f);
  for_each_light_sample(x, rng, World::kIncluded, [&](const LightSample& s) {
    if (glm::dot(x.geometric_normal, s.direction) <= 0.0f) return;
    const glm::vec3 reflected = bsdf.reflected(s.direction);
    if (!(max_component(reflected) > 0.0f)) return;
    const float weight = s.pdf > 0.0f ? power_heuristic(s.pdf, bsdf.pdf(s.direction)) : 1.0f;
    if (!(weight > 0.0f) || !unoccluded(x, s, rays)) return;
    radiance += s.contribution * reflected * weight;
  });
  return radiance;
}

glm::vec3 DirectLight::emission_along(const glm::vec3& position, const glm::vec3& direction,
                                      const Hit& hit, float bsdf_pdf) const {
  return emission_along(position, direction, hit, bsdf_pdf, World::kIncluded);
}

glm::vec3 DirectLight::emission_along(const glm::vec3& position, const glm::vec3& direction,
                                      const Hit& hit, float bsdf_pdf, World world) const {
  glm::vec3 radiance(0.0f);
  const float t_max = hit.hit ? hit.t : 1e30f;
  LightHit light_hit;
  for (const PointLight& light : point_lights_) {
    if (light.intersect(position, direction, t_max, light_hit)) {
      radiance += light_hit.radiance * power_heuristic(bsdf_pdf, light_hit.pdf);
    }
  }
  for (const AreaLight& light : area_lights_) {
    if (light.intersect(position, direction, t_max, light_hit)) {
      radiance += light_hit.radiance * power_heuristic(bsdf_pdf, light_hit.pdf);
    }
  }
  if (hit.hit) {
    // Not emissive_triangles_.empty(): emitters whose estimated power is 0 are never light
    // sampled, but any light they do emit must still be found by this ray (MIS weight 1).
    if (scene_.emissive_triangles.empty()) return radiance;
    const glm::vec3 emitted = emissive_triangles_.emitted(hit.triangle, hit.b1, hit.b2, direction);
    if (max_component(emitted) > 0.0f) {
      const Triangle& t = scene_.triangles[hit.triangle];
      const float cos_light = std::abs(glm::dot(t.face_normal, direction));
      const float light_pdf =
          emissive_triangles_.pdf(hit.triangle, hit.b1, hit.b2, hit.t, cos_light);
      radiance += emitted * power_heuristic(bsdf_pdf, light_pdf);
    }
    return radiance;
  }
  for (const SunLight& light : sun_lights_) {
    if (light.intersect(direction, light_hit)) {
      radiance += light_hit.radiance * power_heuristic(bsdf_pdf, light_hit.pdf);
    }
  }
  if (world == World::kExcluded) return radiance;
  const float share = portal_share(position);
  if (share > 0.0f) {
    const glm::vec3 sky = environment_ ? environment_->radiance(direction) : world_radiance_;
    const float light_pdf = world_pdf(position, direction, share);
    return radiance + sky * (light_pdf > 0.0f ? power_heuristic(bsdf_pdf, light_pdf) : 1.0f);
  }
  if (environment_) {
    float light_pdf = 0.0f;
    const glm::vec3 sky = environment_->radiance(direction, light_pdf);
    return radiance + sky * power_heuristic(bsdf_pdf, light_pdf);
  }
  // No light sampling for a constant world: weight 1.
  return radiance + world_radiance_;
}

glm::vec3 DirectLight::cosine_ray_irradiance(const SurfacePoint& x, RandomStream& rng,
                                             uint64_t& rays, glm::vec3& direction,
                                             World world) const {
  const float u1 = rng.next_float(), u2 = rng.next_float();
  const glm::vec3 local = sample_cosine_hemisphere(u1, u2);
  direction = Frame(x.shading_normal).to_world(local);
  const float bsdf_pdf = local.z * kInvPi;
  if (!(bsdf_pdf > 0.0f) || glm::dot(direction, x.geometric_normal) <= 0.0f) {
    return glm::vec3(0.0f);
  }
  const glm::vec3 origin = ray_origin(x);
  ++rays;
  const Hit hit = tracer_.intersect(Ray{origin, direction, 0.0f, 1e30f});
  // E = integral of L cos; with density cos / pi, one sample estimates pi * L.
  return kPi * emission_along(x.position, direction, hit, bsdf_pdf, world);
}

glm::vec3 DirectLight::irradiance_sample(const SurfacePoint& x, RandomStream& rng, uint64_t& rays,
                                         World world) const {
  const glm::vec3 irradiance =
      light_sample_irradiance(x, rng, rays, world, [](const glm::vec3&, const glm::vec3&) {});
  glm::vec3 direction;
  return irradiance + cosine_ray_irradiance(x, rng, rays, direction, world);
}

glm::vec3 DirectLight::irradiance_sample_terms(const SurfacePoint& x, RandomStream& rng,
                                               uint64_t& rays,
                                               const IrradianceTermVisitor& visit) const {
  // irradiance_sample term by term, in the same order.
  const glm::vec3 irradiance = light_sample_irradiance(x, rng, rays, World::kIncluded, visit);
  glm::vec3 direction;
  const glm::vec3 term = cosine_ray_irradiance(x, rng, rays, direction);
  if (max_component(term) > 0.0f) visit(direction, term);
  return irradiance + term;
}

}  // namespace bakegi
