// Direct light at surface points: next-event estimation (one shadow-ray sample of every lamp
// and one of the emissive triangles) combined by multiple importance sampling (power
// heuristic) with cosine-weighted sampling of the diffuse BSDF, whose rays pick up emission
// from area, sphere and sun lights, emissive triangles and the world.
//
// Split in two halves so the path tracer can use them at every vertex:
//   sample_lights()   the light-sampling half (shadow rays included);
//   emission_along()  the BSDF-sampling half for a ray already traced.
// irradiance_sample() puts both together for one sample of E_direct at a point.
//
// All lights are in radiometric units (bakegi.h). Lamps are not geometry: they neither
// occlude rays nor are hit by them except through emission_along (as in Cycles).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "lights/area_light.h"
#include "lights/emissive_triangles.h"
#include "lights/environment_light.h"
#include "lights/lamp_shadow_cache.h"
#include "lights/point_light.h"
#include "lights/sun_light.h"
#include "lights/surface_point.h"
#include "lights/world_portals.h"
#include "scene/ray_tracer.h"
#include "scene/surface_bsdf.h"

namespace bakegi {

class RandomStream;

class DirectLight {
 public:
  DirectLight(const Scene& scene, const RayTracer& tracer);

  // Offset of ray origins off surfaces, relative to the scene's size.
  float ray_epsilon() const { return ray_epsilon_; }
  glm::vec3 ray_origin(const SurfacePoint& x) const {
    return x.position + x.geometric_normal * ray_epsilon_;
  }

  // Light-sampling estimate of the direct irradiance E (W/m^2) at x, each lamp's sample
  // weighted against cosine-weighted BSDF sampling (delta lights get weight 1). Counts the
  // shadow rays into `rays`.
  glm::vec3 sample_lights(const SurfacePoint& x, RandomStream& rng, uint64_t& rays) const;

  // Light sampling alone, unweighted: one sample of every lamp and of the emissive triangles
  // (one shadow ray each), an unbiased estimate of their direct irradiance E at x; the world
  // is left out (only a BSDF ray finds it). Half the rays of irradiance_sample where the
  // world is black, and noisier where a small light is seen at a grazing angle (the preview
  // uses it; bakes use the MIS estimate).
  glm::vec3 lamp_irradiance(const SurfacePoint& x, RandomStream& rng, uint64_t& rays) const;

  // The same light samples for a general BSDF (glossy materials): the light-sampling
  // estimate of the radiance `bsdf` reflects (Σ contribution · f cos), each sample weighted
  // against the BSDF's own sampling density. Consumes the same random numbers as above.
  glm::vec3 sample_lights(const SurfacePoint& x, const SurfaceBsdf& bsdf, RandomStream& rng,
                          uint64_t& rays) const;

  // BSDF-sampling counterpart: the MIS-weighted radiance arriving at the surface point
  // `position` along the unit `direction` (drawn with solid-angle density bsdf_pdf), given
  // the hit of the ray traced from ray_origin(): lamp shapes crossed before the hit, the hit
  // triangle's emission, or on a miss the sun and the world.
  glm::vec3 emission_along(const glm::vec3& position, const glm::vec3& direction, const Hit& hit,
                           float bsdf_pdf) const;

  // Whether an irradiance sample includes the world's light. A caller that integrates the
  // world (a uniform colour) exactly from sky visibility excludes it here: one cosine ray per
  // sample finds a small skylight too rarely.
  enum class World { kIncluded, kExcluded };

  // One sample of the direct irradiance E at x: sample_lights plus one cosine-weighted ray.
  glm::vec3 irradiance_sample(const SurfacePoint& x, RandomStream& rng, uint64_t& rays,
                              World world = World::kIncluded) const;

  // Receives one term of an irradiance sample: the unit direction from x towards where the
  // light comes from and the MIS-weighted irradiance (W/m², receiver cosine included) it adds.
  using IrradianceTermVisitor =
      std::function<void(const glm::vec3& direction, const glm::vec3& irradiance)>;
  // irradiance_sample split by direction, for callers that need where E_direct comes from
  // (glossy reflection of direct light): the same random numbers, rays and arithmetic, so the
  // returned sum is bit-identical to irradiance_sample's; every non-zero term (each unoccluded
  // lamp / emissive-triangle sample, then the cosine-weighted ray's pick-up of emission and
  // the world) is also handed to `visit`.
  glm::vec3 irradiance_sample_terms(const SurfacePoint& x, RandomStream& rng, uint64_t& rays,
                                    const IrradianceTermVisitor& visit) const;

  // The lamps (point and spot, area, sun lights, in that order) one by one, for the pilot
  // of LampShadowCache.
  size_t lamp_count() const {
    return point_lights_.size() + area_lights_.size() + sun_lights_.size();
  }
  bool lamp_casts_shadow(size_t lamp) const;
  bool sample_lamp(size_t lamp, const glm::vec3& position, float u1, float u2,
                   LightSample& out) const;
  // Traces the shadow ray of a light sample (counted in `rays`); true when nothing blocks it.
  bool unoccluded(const SurfacePoint& x, const LightSample& s, uint64_t& rays) const;
  // Skips most lamp samples where the cache found the lamp blocked (lamp_shadow_cache.h);
  // null: every sample traced. The cache must outlive this object.
  void set_shadow_cache(const LampShadowCache* cache) { shadow_cache_ = cache; }

  const Scene& scene() const { return scene_; }
  const RayTracer& tracer() const { return tracer_; }
  // The world's radiance, the same from every direction (W/(m² sr)); with a world image its
  // mean (the light samples and rays of this class use the image itself).
  const glm::vec3& world_radiance() const { return world_radiance_; }
  // Whether the world is an image (sampled with the lamps) rather than a constant.
  bool has_environment() const { return environment_ != nullptr; }

 private:
  // Calls visit(sample) for one sample of every lamp and one of the emissive triangles, and
  // with the world included one of the world's image where it has one.
  template <typename Visit>
  void for_each_light_sample(const SurfacePoint& x, RandomStream& rng, World world,
                             Visit&& visit) const;
  // The BSDF-sampling half of irradiance_sample: one cosine-weighted ray (its direction into
  // `direction`) and π times the MIS-weighted emission it picks up; 0 below the surface.
  glm::vec3 cosine_ray_irradiance(const SurfacePoint& x, RandomStream& rng, uint64_t& rays,
                                  glm::vec3& direction, World world = World::kIncluded) const;
  // emission_along, with or without the world on a miss.
  glm::vec3 emission_along(const glm::vec3& position, const glm::vec3& direction, const Hit& hit,
                           float bsdf_pdf, World world) const;
  // The light-sampling half of the irradiance: Σ MIS-weighted unoccluded samples, each
  // term also handed to visit(direction, term).
  template <typename Visit>
  glm::vec3 light_sample_irradiance(const SurfacePoint& x, RandomStream& rng, uint64_t& rays,
                                    World world, Visit&& visit) const;
  // Where x sees a portal (`share` = portal_share(x) > 0): one sample of the world's light
  // from x, through the portals or (with a world image) by the image's light.
  bool sample_world_through_portals(const glm::vec3& x, float share, RandomStream& rng,
                                    LightSample& out) const;
  // The share of the world's light samples that aim through the portals at x: 0 where x
  // sees none, 1/2 with a world image (the image's sampler keeps the sun and the rest),
  // 1 with a constant world (bounced rays find the sky outside the portals).
  float portal_share(const glm::vec3& x) const;
  // The solid-angle density of the world's light sample at x (share = portal_share(x)) for
  // the unit direction; 0 where the world is not light-sampled (a constant world unseen by
  // portals).
  float world_pdf(const glm::vec3& x, const glm::vec3& direction, float share) const;

  const Scene& scene_;
  const RayTracer& tracer_;
  float ray_epsilon_;
  std::vector<PointLight> point_lights_;  // point and spot
  std::vector<SunLight> sun_lights_;
  std::vector<AreaLight> area_lights_;
  EmissiveTriangles emissive_triangles_;
  glm::vec3 world_radiance_;
  const EnvironmentLight* environment_;  // the scene's, or null: the world is world_radiance_
  WorldPortals portals_;
  const LampShadowCache* shadow_cache_ = nullptr;
};

}  // namespace bakegi
