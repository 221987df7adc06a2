// The path tracer with a radiance cache as control variate (issue 15, item 4): one sample of
// E_indirect/π at a bake point p whose Monte Carlo part carries the cache's error rather than
// the whole signal.
//
// sample_indirect's value for a first ray p -> x1 (albedo ρ at x1) is S = F + R: F the light
// sample at x1 (ρ/π times the next-event estimate of E_direct(x1), a shadow ray per lamp) and
// R the rest of the path, whose mean is ρ/π (the rest of E_direct(x1) + E_indirect(x1)). With
// the cache's C = ρ E_indirect,cache(x1)/π (solvers/radiance_cache.h) the same mean is
//
//     E[S] = E[F + C] + E[R - C],
//
// and the second term, the residual, can be sampled less often than the first: the path goes
// on beyond its first light sample with probability q and its residual is weighted 1/q
// (PathContinuation), so one sample is
//
//     F + C + (B / q) (R - C),   B = 1 with probability q, else 0.
//
// Unbiased for any cache and any q in (0, 1]: a poor cache only makes R - C larger. Where
// the cache is good, R - C is small and most samples stop after two or three rays instead of
// the path's five or six. The sample's variance is A + M / q with M = E[(R - C)^2] and
// A = Var(S) - M; its cost is c1 + q c2 (rays to the first light sample, rays after it), so
// q* = sqrt(M c1 / (A c2)) minimises variance x cost (ResidualStatistics).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "lights/surface_point.h"

namespace bakegi {

class DirectLight;
class RadianceCache;
class RandomStream;

// One sample as above with q = rest_probability (in (0, 1]).
glm::vec3 sample_indirect_controlled(const DirectLight& direct, const RadianceCache& cache,
                                     const SurfacePoint& point, RandomStream& rng,
                                     int max_bounces, float rest_probability, uint64_t& rays);

// The parts of one sample with q = 1, for measuring the residual: S = F + R, the control C,
// and the rays before and after the first light sample.
struct ControlledSampleParts {
  glm::vec3 first_light{0.0f};  // F
  glm::vec3 rest{0.0f};         // R
  glm::vec3 control{0.0f};      // C
  uint64_t first_rays = 0;  // the first ray and the first light sample's shadow rays
  uint64_t rest_rays = 0;
};
ControlledSampleParts sample_controlled_parts(const DirectLight& direct,
                                              const RadianceCache& cache,
                                              const SurfacePoint& point, RandomStream& rng,
                                              int max_bounces);

// Per-sample spreads of a pilot (luminance, pooled over points), and the q they imply.
class ResidualStatistics {
 public:
  // Adds one point's samples (all with q = 1).
  void add_point(const ControlledSampleParts* samples, size_t count);
  // sqrt(mean per-point variance of S) / mean S: the plain path tracer's per-sample spread.
  double path_spread() const;
  // sqrt(mean per-point E[(R - C)^2]) / mean S: what the residual leaves.
  double residual_spread() const;
  // q* clamped to [min_probability, 1]; 1 when the pilot has too little to say.
  double best_rest_probability(double min_probability) const;
  // Rays per sample before / after the first light sample.
  double first_rays() const;
  double rest_rays() const;

 private:
  double points_ = 0.0, samples_ = 0.0;
  double mean_sum_ = 0.0;      // Σ over points of the mean of S
  double variance_sum_ = 0.0;  // Σ over points of Var(S)
  double residual_sum_ = 0.0;  // Σ over points of E[(R - C)^2]
  double first_rays_ = 0.0, rest_rays_ = 0.0;
};

}  // namespace bakegi
