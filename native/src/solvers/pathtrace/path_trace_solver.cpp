#include "solvers/pathtrace/path_trace_solver.h"

#include "lights/direct_light.h"
#include "settings/settings.h"
#include "solvers/pathtrace/indirect_path.h"
#include "solvers/pathtrace/irradiance_cache_bake.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi {

PathTraceSettings PathTraceSettings::from(const Settings& settings) {
  PathTraceSettings s;
  s.sampling = SampleSettings::from(settings);
  const SettingReader reader(settings, method_schema("pathtrace"));
  s.max_bounces = int(reader.get_int("max_bounces"));
  s.irradiance_cache = reader.get_float("irradiance_cache");
  if (s.irradiance_cache > 0.0) {
    if (s.sampling.samples < kIrradianceCacheMinSamples) {
      throw Error(
          BAKEGI_ERROR_INVALID_ARGUMENT,
          "irradiance_cache needs samples >= " + std::to_string(kIrradianceCacheMinSamples) +
              " (paths per record: one for each gradient cell)");
    }
  }
  return s;
}

PathTracedField::PathTracedField(const DirectLight& direct, const PathTraceSettings& settings)
    : direct_(direct), settings_(settings) {}

bool PathTracedField::evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                                             std::span<float> variance_of_mean,
                                             const NoiseFilter* after, JobContext& context) const {
  const int max_bounces = settings_.max_bounces;
  if (settings_.irradiance_cache > 0.0) {
    IrradianceCacheSettings cache;
    cache.accuracy = float(settings_.irradiance_cache);
    cache.samples = settings_.sampling.samples;
    cache.seed = settings_.sampling.seed;
    cache.sample_offset = settings_.sampling.sample_offset;
    cache.max_bounces = max_bounces;
    cache.target_error = settings_.sampling.target_error;
    if (bake_with_irradiance_cache(direct_, points, cache, out, variance_of_mean, context)) {
      return !variance_of_mean.empty();
    }
  }
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
