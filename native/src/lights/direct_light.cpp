#include "lights/direct_light.h"

#include <algorithm>
#include <cmath>
#include <cstring>
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

// A uniform number in [0, 1) from a light sample's two numbers and its lamp: independent of
// them as a good hash is, so a decision on it keeps the estimate unbiased.
float keep_number(float u1, float u2, size_t lamp) {
  uint32_t a, b;
  std::memcpy(&a, &u1, sizeof a);
  std::memcpy(&b, &u2, sizeof b);
  const uint64_t h = mix64((uint64_t(a) << 32 | b) ^ mix64(uint64_t(lamp) + 0x9E3779B97F4A7C15ull));
  return float(h >> 40) * (1.0f / 16777216.0f);
}

// A shadow ray's seed (Ray::seed) from the numbers its light sample was drawn with.
uint32_t shadow_seed(float u1, float u2, size_t salt) {
  return uint32_t(keep_number(u1, u2, salt) * 16777216.0f);
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

bool DirectLight::lamp_casts_shadow(size_t lamp) const {
  if (lamp < point_lights_.size()) return point_lights_[lamp].casts_shadow();
  lamp -= point_lights_.size();
  if (lamp < area_lights_.size()) return area_lights_[lamp].casts_shadow();
  lamp -= area_lights_.size();
  return lamp < sun_lights_.size() && sun_lights_[lamp].casts_shadow();
}

bool DirectLight::sample_lamp(size_t lamp, const glm::vec3& position, float u1, float u2,
                              LightSample& out) const {
  out.casts_shadow = lamp_casts_shadow(lamp);
  if (lamp < point_lights_.size()) return point_lights_[lamp].sample(position, u1, u2, out);
  lamp -= point_lights_.size();
  if (lamp < area_lights_.size()) return area_lights_[lamp].sample(position, u1, u2, out);
  lamp -= area_lights_.size();
  return lamp < sun_lights_.size() && sun_lights_[lamp].sample(u1, u2, out);
}

template <typename Visit>
void DirectLight::for_each_light_sample(const SurfacePoint& x, RandomStream& rng, World world,
                                        Visit&& visit) const {
  LightSample s;
  const size_t lamps = lamp_count();
  for (size_t k = 0; k < lamps; ++k) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    if (!sample_lamp(k, x.position, u1, u2, s)) continue;
    if (shadow_cache_) {
      // Where the pilot found this lamp blocked, a sample is kept with probability q and
      // weighed 1/q. The decision hashes the sample's own numbers instead of drawing one, so
      // that every other number of the path, and the bake wherever nothing is skipped, stay
      // as they are without the cache.
      const float kept = shadow_cache_->kept_probability(k, x.position, x.geometric_normal);
      if (kept < 1.0f) {
        if (keep_number(u1, u2, k) >= kept) continue;
        s.contribution /= kept;
      }
    }
    s.seed = shadow_seed(u1, u2, k);
    visit(s);
  }
  s.casts_shadow = true;  // emissive triangles and the world
  if (!emissive_triangles_.empty()) {
    const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    if (emissive_triangles_.sample(x.position, u0, u1, u2, s)) {
      s.seed = shadow_seed(u1 + u0, u2, lamps);
      visit(s);
    }
  }
  // Last, so that scenes without a world image draw the same numbers as before.
  if (world == World::kExcluded) return;
  // Where no portal is seen, exactly as without portals (the same random numbers).
  const float share = portal_share(x.position);
  if (share > 0.0f) {
    if (sample_world_through_portals(x.position, share, rng, s)) visit(s);
  } else if (environment_) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    if (environment_->sample(u1, u2, s)) {
      s.seed = shadow_seed(u1, u2, lamps + 1);
      visit(s);
    }
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
  Ray shadow{origin, s.direction, 0.0f, 1e30f, s.seed};
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
