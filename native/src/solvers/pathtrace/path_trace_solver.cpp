#include "solvers/pathtrace/path_trace_solver.h"

#include <chrono>
#include <optional>

#include "lights/direct_light.h"
#include "solvers/pathtrace/direction_guide.h"
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
  s.guide_paths = reader.get_int("guide_paths");
  return s;
}

PathTracedField::PathTracedField(const DirectLight& direct, const PathTraceSettings& settings)
    : direct_(direct), settings_(settings) {}

bool PathTracedField::evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                                             std::span<float> variance_of_mean,
                                             const NoiseFilter* after, JobContext& context) const {
  const int max_bounces = settings_.max_bounces;
  std::optional<DirectionGuide> guide;
  if (settings_.guide_paths > 0 && points.size() > 0) {
    const auto start = std::chrono::steady_clock::now();
    context.set_stage_text("learning where the light comes from");
    guide.emplace(direct_, points, int(settings_.guide_paths), max_bounces,
                  uint64_t(settings_.sampling.seed) ^ kGuideSalt, context);
    Report& report = context.report();
    report.add_count("rays", guide->rays());
    report.set_number("guide_regions", double(guide->regions()));
    report.add_seconds("guide", std::chrono::duration<double>(
                                    std::chrono::steady_clock::now() - start)
                                    .count());
  }
  const DirectionGuide* guiding = guide ? &*guide : nullptr;
  estimate_at_points(
      points, out, settings_.sampling,
      [&](const SurfacePoint& x, RandomStream& rng, uint64_t& rays) {
        return guiding ? sample_indirect_guided(direct_, *guiding, x, rng, max_bounces, rays)
                       : sample_indirect(direct_, x, rng, max_bounces, rays);
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
