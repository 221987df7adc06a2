// The Monte Carlo reference solver ("pathtrace"). Solving does no work: the returned field
// traces paths at whatever points it is evaluated at (indirect_path.h).
// Settings: the common sampling ones (samples, seed, sample_offset) and setting_specs().
#pragma once

#include <memory>
#include <string>

#include "solvers/point_sampling.h"
#include "solvers/solver.h"

namespace bakegi {

class LitSurfaces;

struct PathTraceSettings {
  SampleSettings sampling;
  int max_bounces = 64;
  // "auto", "on" or "off": whether gathers also pick points on the directly lit surfaces
  // (lit_surfaces.h); auto where the lit power is concentrated (PathTraceSolver::solve).
  std::string lit_surfaces = "auto";

  static PathTraceSettings from(const Settings& settings);
};

class PathTracedField : public SampledField {
 public:
  // `direct` (and the scene and tracer it refers to) must outlive the field.
  // `lit`: the lit surfaces to sample as well, or null for plain path tracing.
  PathTracedField(const DirectLight& direct, const PathTraceSettings& settings,
                  std::shared_ptr<const LitSurfaces> lit = nullptr);
  bool evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                              std::span<float> variance_of_mean, const NoiseFilter* after,
                              JobContext& context) const override;

 private:
  const DirectLight& direct_;
  PathTraceSettings settings_;
  std::shared_ptr<const LitSurfaces> lit_;
};

class PathTraceSolver : public Solver {
 public:
  static const std::vector<SettingSpec>& setting_specs();
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;

 private:
  static constexpr uint64_t kMinLitCells = 65536;
  static constexpr uint64_t kMaxLitCells = uint64_t(1) << 20;
  // "auto" samples the lit surfaces when their power is spread over less than this part of
  // the area (LitSurfaces::spread()).
  static constexpr double kLitSpreadForAuto = 0.25;
  static constexpr uint64_t kLitSurfaceSalt = 0x11C5F0A7E5ull;
  // The lit surfaces the field samples as well, or null (setting off, auto on evenly lit
  // scenes, or not within the memory budget: then with a warning).
  static std::shared_ptr<const LitSurfaces> lit_surfaces_for(const SolveInputs& inputs,
                                                             const PathTraceSettings& settings,
                                                             JobContext& context);
};

}  // namespace bakegi
