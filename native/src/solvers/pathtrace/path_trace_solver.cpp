#include "solvers/pathtrace/path_trace_solver.h"

#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "util/job_context.h"
#include "settings/settings.h"

namespace bakegi {

PathTraceSettings PathTraceSettings::from(const Settings& settings) {
  PathTraceSettings s;
  s.sampling = SampleSettings::from(settings);
  s.max_bounces = int(SettingReader(settings, method_schema("pathtrace")).get_int("max_bounces"));
  return s;
}

PathTracedField::PathTracedField(const DirectLight& direct, const PathTraceSettings& settings)
    : direct_(direct), settings_(settings) {}

bool PathTracedField::evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                                             std::span<float> variance_of_mean,
                                             const NoiseFilter* after, JobContext& context) const {
  const int max_bounces = settings_.max_bounces;
  estimate_at_points(
      points, out, settings_.sampling,
      [&](const SurfacePoint& x, RandomStream& rng, uint64_t& rays) {
        return sample_indirect(direct_, x, rng, max_bounces, rays);
      },
      context, variance_of_mean, after);
  return !variance_of_mean.empty();
}

std::unique_ptr<IndirectField> PathTraceSolver::solve(const SolveInputs& inputs,
                                                      JobContext& context) {
  // Settings are read here so that a bad value fails before any tracing starts.
  return std::make_unique<PathTracedField>(inputs.direct, PathTraceSettings::from(inputs.settings));
}

}  // namespace bakegi
