// One sample of the indirect light at a bake point, in the output convention E_indirect/pi.
//
// From the point p (normal n) a cosine-weighted direction is traced to the first hit x1.
// With density cos/pi the sample of E/pi = integral of L cos/pi is simply the radiance
// arriving from x1, of which only the part x1 reflects counts: emission at x1, lamps
// crossed on the way and the world on a miss are direct light at p and excluded. At x1
// and every later vertex x_k (diffuse, two-sided, albedo rho_k):
//   reflected radiance = rho_k / pi * E(x_k),
//   E(x_k) = next-event estimate (MIS-weighted) + pi * L along a cosine-sampled ray
//            (emission found by that ray MIS-weighted, then the next vertex's reflection),
// so the path throughput is multiplied by rho_k per bounce. A vertex whose material has a
// glossy lobe uses the same two strategies with the diffuse + Phong mixture of
// scene/surface_bsdf.h (f cos in the light samples, the mixture's density in MIS, f cos / pdf
// in the throughput); diffuse vertices keep the path above exactly, random numbers included.
// Russian roulette after a few bounces keeps it unbiased; max_bounces caps the number of reflecting
// vertices (the last one still traces its BSDF ray so that emission MIS stays consistent).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "lights/surface_point.h"

namespace bakegi {

class DirectLight;
class RandomStream;

glm::vec3 sample_indirect(const DirectLight& direct, const SurfacePoint& point, RandomStream& rng,
                          int max_bounces, uint64_t& rays);

// The radiance a path reflects back along -direction from `hit` (the first hit of a ray
// from the bake point along `direction`), in two parts: the first vertex's light sample
// (next-event estimate) and the rest of the path (its BSDF ray's emission and every later
// vertex). first_light + rest is sample_indirect's value for that first ray.
struct PathRadiance {
  glm::vec3 first_light{0.0f};
  glm::vec3 rest{0.0f};  // already multiplied by rest_weight
  // What the continuation returned (1 without one); 0: the path stopped at the first light
  // sample. Also 0 when the first hit reflects nothing (the continuation was not asked).
  float rest_weight = 0.0f;
};

// Decides after the first vertex's light sample whether the path goes on, and returns the
// weight of the rest (1 / the probability of going on: the rest stays unbiased), or 0 to stop
// there. May draw from `rng`.
class PathContinuation {
 public:
  virtual float weight_of_rest(RandomStream& rng) const = 0;

 protected:
  ~PathContinuation() = default;
};

// `continuation` null: the path always goes on (weight 1).
PathRadiance trace_from_first_hit(const DirectLight& direct, const Hit& hit,
                                  const glm::vec3& direction, RandomStream& rng, int max_bounces,
                                  uint64_t& rays, const PathContinuation* continuation = nullptr);

// The cosine-weighted first direction of sample_indirect at `point` (2 draws of `rng`) and
// the ray origin it leaves from; pdf 0 where the direction is degenerate.
struct FirstRay {
  glm::vec3 origin;
  glm::vec3 direction;
  float pdf;
};
FirstRay sample_first_ray(const DirectLight& direct, const SurfacePoint& point,
                          RandomStream& rng);

}  // namespace bakegi
