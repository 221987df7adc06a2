// What a grid vertex's ray sees (Pacanowski et al. 2008, §3.1: "one may use any global
// illumination algorithm"): the radiance the surface it hits reflects back along the ray,
// from the bake's own solver, so the grid holds the scene's full lighting for receivers that
// were never bake points:
//   - the path tracer: one path continued from the hit (indirect_path.h), unbiased; the
//     grid's many rays per hemisphere average its noise;
//   - any other method: rho / pi * (one sample of the direct irradiance at the hit) + rho *
//     the method's indirect field there (its value is E_indirect / pi), diffuse.
// Emission at the hit is direct light for the receiver and is left out, as in every bake.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"

namespace bakegi {

class DirectLight;
class IndirectField;
class JobContext;

// A grid ray that hit a surface: its unit direction, the hit, and a key naming the ray
// (vertex, hemisphere, ray) that seeds its random numbers, so results do not depend on
// threads or chunking.
struct GridRayHit {
  glm::vec3 direction;
  Hit hit;
  uint64_t key = 0;
};

class HitRadiance {
 public:
  virtual ~HitRadiance() = default;
  // out[i]: the radiance reflected back along -hits[i].direction (RGB, W / (m^2 sr)). Adds
  // the rays it traced to `rays`. Parallel inside; honours cancel through the context.
  virtual void evaluate(std::span<const GridRayHit> hits, std::span<glm::vec3> out, uint64_t seed,
                        JobContext& context, uint64_t& rays) const = 0;
};

// The path tracer's when `field` is the path tracer's field (its max_bounces), else the
// direct light plus `field`. `direct` and `field` must outlive the result.
std::unique_ptr<HitRadiance> make_hit_radiance(const DirectLight& direct,
                                               const IndirectField& field);

}  // namespace bakegi
