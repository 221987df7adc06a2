#include "solvers/pathtrace/path_trace_solver.h"

#include <algorithm>
#include <chrono>

#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "solvers/pathtrace/lit_surfaces.h"
#include "util/job_context.h"
#include "util/report.h"
#include "settings/settings.h"

namespace bakegi {

PathTraceSettings PathTraceSettings::from(const Settings& settings) {
  PathTraceSettings s;
  s.sampling = SampleSettings::from(settings);
  const SettingReader reader(settings, method_schema("pathtrace"));
  s.max_bounces = int(reader.get_int("max_bounces"));
  s.lit_surfaces = reader.get_string("lit_surfaces");
  return s;
}

PathTracedField::PathTracedField(const DirectLight& direct, const PathTraceSettings& settings,
                                 std::shared_ptr<const LitSurfaces> lit)
    : direct_(direct), settings_(settings), lit_(std::move(lit)) {}

bool PathTracedField::evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                                             std::span<float> variance_of_mean,
                                             const NoiseFilter* after, JobContext& context) const {
  const int max_bounces = settings_.max_bounces;
  const LitSurfaces* lit = lit_.get();
  estimate_at_points(
      points, out, settings_.sampling,
      [&](const SurfacePoint& x, RandomStream& rng, uint64_t& rays) {
        return lit ? sample_indirect_lit(direct_, *lit, x, rng, max_bounces, rays)
                   : sample_indirect(direct_, x, rng, max_bounces, rays);
      },
      context, variance_of_mean, after);
  return !variance_of_mean.empty();
}

std::unique_ptr<IndirectField> PathTraceSolver::solve(const SolveInputs& inputs,
                                                      JobContext& context) {
  // Settings are read here so that a bad value fails before any tracing starts.
  const PathTraceSettings settings = PathTraceSettings::from(inputs.settings);
  return std::make_unique<PathTracedField>(inputs.direct, settings,
                                           lit_surfaces_for(inputs, settings, context));
}

std::shared_ptr<const LitSurfaces> PathTraceSolver::lit_surfaces_for(
    const SolveInputs& inputs, const PathTraceSettings& settings, JobContext& context) {
  if (settings.lit_surfaces == "off") return nullptr;
  // Cells follow the geometry, not the bake points (a subset of points samples the same
  // light): about two a triangle, at least kMinLitCells so that the few large triangles of
  // a simple room still resolve a lit patch.
  const uint64_t target =
      std::clamp<uint64_t>(2 * inputs.scene.triangles.size(), kMinLitCells, kMaxLitCells);
  Report& report = context.report();
  const uint64_t cells = LitSurfaces::cell_count(inputs.direct, target);
  const uint64_t bytes = cells * LitSurfaces::kBytesPerCell + inputs.scene.triangles.size() * 5;
  if (bytes > inputs.memory.remaining()) {
    report.warn("lit-surface sampling left out: its " + MemoryBudget::megabytes(bytes) +
                " do not fit in what is left of " + inputs.memory.describe());
    return nullptr;
  }
  const auto start = std::chrono::steady_clock::now();
  auto lit = std::make_shared<const LitSurfaces>(
      inputs.direct, target, uint64_t(settings.sampling.seed) ^ kLitSurfaceSalt, context);
  report.add_seconds("lit_surfaces",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                         .count());
  report.add_count("rays", lit->rays());
  report.set_number("lit_surface_cells", double(lit->cells()));
  report.set_number("lit_surface_spread", lit->spread());
  const bool use = !lit->empty() &&
                   (settings.lit_surfaces == "on" || lit->spread() < kLitSpreadForAuto);
  report.set_number("lit_surfaces_used", use ? 1.0 : 0.0);
  return use ? lit : nullptr;
}

}  // namespace bakegi
