#include "solvers/pathtrace/controlled_path_field.h"

#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "solvers/pathtrace/controlled_path.h"
#include "solvers/radiance_cache.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/report.h"

namespace bakegi {

ControlledPathField::ControlledPathField(const DirectLight& direct,
                                         std::shared_ptr<const RadianceCache> cache,
                                         const PathTraceSettings& settings,
                                         double rest_probability)
    : direct_(direct),
      cache_(std::move(cache)),
      settings_(settings),
      rest_probability_(rest_probability) {}

double ControlledPathField::pilot(const BakePoints& points, JobContext& context) const {
  const size_t count = std::min(points.size(), kPilotPoints);
  if (count == 0) return 1.0;
  // Its own random streams (another seed), so the bake's samples stay those of the seed.
  const uint64_t seed = uint64_t(settings_.sampling.seed) ^ 0x70696c6f74ull;
  std::vector<ControlledSampleParts> parts(count * kPilotSamples);
  std::vector<uint64_t> rays(count, 0);
  tbb::parallel_for(size_t(0), count, [&](size_t k) {
    context.throw_if_cancelled();
    const size_t i = k * points.size() / count;
    const SurfacePoint x{points.positions[i], points.normals[i], points.normals[i]};
    for (int s = 0; s < kPilotSamples; ++s) {
      RandomStream rng = sobol_sample_stream(seed, i, uint64_t(s));
      ControlledSampleParts& p = parts[k * kPilotSamples + size_t(s)];
      p = sample_controlled_parts(direct_, *cache_, x, rng, settings_.max_bounces);
      rays[k] += p.first_rays + p.rest_rays;
    }
  });
  ResidualStatistics statistics;
  uint64_t all_rays = 0;
  for (size_t k = 0; k < count; ++k) {
    statistics.add_point(&parts[k * kPilotSamples], kPilotSamples);
    all_rays += rays[k];
  }
  Report& report = context.report();
  report.add_count("rays", all_rays);
  report.set_number("residual_path_spread", statistics.path_spread());
  report.set_number("residual_spread", statistics.residual_spread());
  report.set_number("residual_first_rays", statistics.first_rays());
  report.set_number("residual_rest_rays", statistics.rest_rays());
  return statistics.best_rest_probability(kMinRestProbability);
}

bool ControlledPathField::evaluate_with_variance(const BakePoints& points,
                                                 std::span<glm::vec3> out,
                                                 std::span<float> variance_of_mean,
                                                 const NoiseFilter* after,
                                                 JobContext& context) const {
  const double q = rest_probability_ > 0.0 ? rest_probability_ : pilot(points, context);
  context.report().set_number("residual_fraction", q);
  const int max_bounces = settings_.max_bounces;
  const float rest_probability = float(q);
  estimate_at_points(
      points, out, settings_.sampling,
      [&](const SurfacePoint& x, RandomStream& rng, uint64_t& rays) {
        return sample_indirect_controlled(direct_, *cache_, x, rng, max_bounces,
                                          rest_probability, rays);
      },
      context, variance_of_mean, after);
  return !variance_of_mean.empty();
}

}  // namespace bakegi
