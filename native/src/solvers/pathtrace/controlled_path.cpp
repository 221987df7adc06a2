#include "solvers/pathtrace/controlled_path.h"

#include <algorithm>
#include <cmath>

#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "solvers/radiance_cache.h"
#include "util/luminance.h"
#include "util/random.h"

namespace bakegi {

namespace {

// Goes on with probability q, weighting the rest 1/q.
class RandomContinuation : public PathContinuation {
 public:
  explicit RandomContinuation(float probability) : probability_(probability) {}
  float weight_of_rest(RandomStream& rng) const override {
    if (probability_ >= 1.0f) return 1.0f;
    return rng.next_float() < probability_ ? 1.0f / probability_ : 0.0f;
  }

 private:
  float probability_;
};

struct FirstHit {
  Hit hit;
  glm::vec3 direction;
  glm::vec3 control{0.0f};  // C
};

// The first ray and the cache's C at its hit; hit.hit false when nothing reflects.
FirstHit trace_first_hit(const DirectLight& direct, const RadianceCache& cache,
                         const SurfacePoint& point, RandomStream& rng, uint64_t& rays) {
  FirstHit first;
  const FirstRay ray = sample_first_ray(direct, point, rng);
  first.direction = ray.direction;
  if (!(ray.pdf > 0.0f)) return first;
  ++rays;
  first.hit = direct.tracer().intersect(Ray{ray.origin, ray.direction, 0.0f, 1e30f});
  if (!first.hit.hit) return first;
  CachedIrradiance cached;
  if (cache.irradiance_at(first.hit, ray.direction, cached)) {
    const Scene& scene = direct.scene();
    const glm::vec3 albedo =
        scene.albedo_at(scene.triangles[first.hit.triangle], first.hit.b1, first.hit.b2);
    first.control = albedo * cached.indirect_over_pi;
  }
  return first;
}

}  // namespace

glm::vec3 sample_indirect_controlled(const DirectLight& direct, const RadianceCache& cache,
                                     const SurfacePoint& point, RandomStream& rng,
                                     int max_bounces, float rest_probability, uint64_t& rays) {
  const FirstHit first = trace_first_hit(direct, cache, point, rng, rays);
  if (!first.hit.hit) return glm::vec3(0.0f);
  const RandomContinuation continuation(rest_probability);
  const PathRadiance path = trace_from_first_hit(direct, first.hit, first.direction, rng,
                                                 max_bounces, rays, &continuation);
  return path.first_light + first.control + path.rest - path.rest_weight * first.control;
}

ControlledSampleParts sample_controlled_parts(const DirectLight& direct,
                                              const RadianceCache& cache,
                                              const SurfacePoint& point, RandomStream& rng,
                                              int max_bounces) {
  // The first light sample's rays are counted by a continuation that notes the count when
  // it is asked (right after that sample) and always goes on.
  class CountingContinuation : public PathContinuation {
   public:
    explicit CountingContinuation(const uint64_t& rays) : rays_(rays) {}
    float weight_of_rest(RandomStream&) const override {
      at_decision = rays_;
      return 1.0f;
    }
    mutable uint64_t at_decision = 0;

   private:
    const uint64_t& rays_;
  };
  ControlledSampleParts parts;
  uint64_t rays = 0;
  const FirstHit first = trace_first_hit(direct, cache, point, rng, rays);
  parts.first_rays = rays;
  if (!first.hit.hit) return parts;
  const CountingContinuation continuation(rays);
  continuation.at_decision = rays;
  const PathRadiance path = trace_from_first_hit(direct, first.hit, first.direction, rng,
                                                 max_bounces, rays, &continuation);
  parts.first_light = path.first_light;
  parts.rest = path.rest;
  parts.control = first.control;
  parts.first_rays = continuation.at_decision;
  parts.rest_rays = rays - continuation.at_decision;
  return parts;
}

void ResidualStatistics::add_point(const ControlledSampleParts* samples, size_t count) {
  if (count < 2) return;
  double sum = 0.0, squares = 0.0, residual_squares = 0.0;
  for (size_t k = 0; k < count; ++k) {
    const ControlledSampleParts& s = samples[k];
    const double y = luminance(s.first_light + s.rest);
    const double residual = luminance(s.rest - s.control);
    sum += y;
    squares += y * y;
    residual_squares += residual * residual;
    first_rays_ += double(s.first_rays);
    rest_rays_ += double(s.rest_rays);
  }
  const double n = double(count);
  const double mean = sum / n;
  points_ += 1.0;
  samples_ += n;
  mean_sum_ += mean;
  variance_sum_ += std::max(0.0, (squares - n * mean * mean) / (n - 1.0));
  residual_sum_ += residual_squares / n;
}

double ResidualStatistics::path_spread() const {
  if (!(mean_sum_ > 0.0)) return 0.0;
  return std::sqrt(variance_sum_ / points_) / (mean_sum_ / points_);
}

double ResidualStatistics::residual_spread() const {
  if (!(mean_sum_ > 0.0)) return 0.0;
  return std::sqrt(residual_sum_ / points_) / (mean_sum_ / points_);
}

double ResidualStatistics::first_rays() const {
  return samples_ > 0.0 ? first_rays_ / samples_ : 0.0;
}

double ResidualStatistics::rest_rays() const {
  return samples_ > 0.0 ? rest_rays_ / samples_ : 0.0;
}

double ResidualStatistics::best_rest_probability(double min_probability) const {
  // Var = A + M / q, cost = c1 + q c2 (controlled_path.h); A = Var(S) - M.
  const double m = residual_sum_, a = variance_sum_ - residual_sum_;
  const double c1 = first_rays(), c2 = rest_rays();
  if (!(m > 0.0) || !(a > 0.0) || !(c1 > 0.0) || !(c2 > 0.0)) return 1.0;
  return std::clamp(std::sqrt(m * c1 / (a * c2)), min_probability, 1.0);
}

}  // namespace bakegi
