#include "solvers/pathtrace/path_trace_solver.h"

#include <chrono>
#include <cmath>
#include <optional>

#include "lights/direct_light.h"
#include "solvers/pathtrace/final_gather.h"
#include "solvers/pathtrace/indirect_path.h"
#include "util/job_context.h"
#include "util/report.h"
#include "settings/settings.h"

namespace bakegi {

PathTraceSettings PathTraceSettings::from(const Settings& settings) {
  PathTraceSettings s;
  s.sampling = SampleSettings::from(settings);
  const SettingReader reader(settings, method_schema("pathtrace"));
  s.max_bounces = int(reader.get_int("max_bounces"));
  s.final_gather = reader.get_int("final_gather");
  return s;
}

PathTracedField::PathTracedField(const DirectLight& direct, const PathTraceSettings& settings)
    : direct_(direct), settings_(settings) {}

bool PathTracedField::evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                                             std::span<float> variance_of_mean,
                                             const NoiseFilter* after, JobContext& context) const {
  const int max_bounces = settings_.max_bounces;
  SampleSettings sampling = settings_.sampling;
  std::optional<FinalGather> gather;
  if (settings_.final_gather > 0) {
    const auto start = std::chrono::steady_clock::now();
    FinalGatherSettings fg;
    fg.paths = settings_.final_gather;
    fg.target_error = sampling.target_error;
    fg.max_bounces = max_bounces;
    fg.seed = uint64_t(sampling.seed) ^ kGatherCacheSalt;
    gather = build_final_gather(direct_, points, fg, context);
    context.report().add_seconds(
        "final_gather", std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                            .count());
    // The samples aim at what the cache's error leaves of the target (it stays below it).
    if (gather->cache && sampling.target_error > 0.0) {
      sampling.target_error = std::sqrt(sampling.target_error * sampling.target_error -
                                        gather->error * gather->error);
    }
  }
  const GatherCache* cache = gather ? gather->cache.get() : nullptr;
  estimate_at_points(
      points, out, sampling,
      [&](const SurfacePoint& x, RandomStream& rng, uint64_t& rays) {
        return cache ? sample_indirect_gathered(direct_, *cache, x, rng, max_bounces, rays)
                     : sample_indirect(direct_, x, rng, max_bounces, rays);
      },
      context, variance_of_mean, after);
  if (cache) {
    // The predicted error with the cache's part, which no point's own spread shows.
    Report& report = context.report();
    if (report.has_number("sampling_predicted_error")) {
      report.set_number("sampling_predicted_error",
                        std::hypot(report.number("sampling_predicted_error"), gather->error));
      report.set_number("target_error", settings_.sampling.target_error);
    }
  }
  return !variance_of_mean.empty();
}

std::unique_ptr<IndirectField> PathTraceSolver::solve(const SolveInputs& inputs,
                                                      JobContext& context) {
  // Settings are read here so that a bad value fails before any tracing starts.
  return std::make_unique<PathTracedField>(inputs.direct, PathTraceSettings::from(inputs.settings));
}

}  // namespace bakegi
