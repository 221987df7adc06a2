// The Monte Carlo reference solver ("pathtrace"). Solving does no work: the returned field
// traces paths at whatever points it is evaluated at (indirect_path.h).
// Settings: the common sampling ones (samples, seed, sample_offset) and setting_specs().
#pragma once

#include <memory>

#include "solvers/point_sampling.h"
#include "solvers/solver.h"

namespace bakegi {

struct PathTraceSettings {
  SampleSettings sampling;
  int max_bounces = 64;
  // > 0: the accuracy a of an irradiance cache (irradiance_cache_bake.h); 0: every point
  // traces its own paths.
  double irradiance_cache = 0.0;

  static PathTraceSettings from(const Settings& settings);
};

class PathTracedField : public SampledField {
 public:
  // `direct` (and the scene and tracer it refers to) must outlive the field.
  PathTracedField(const DirectLight& direct, const PathTraceSettings& settings);
  bool evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                              std::span<float> variance_of_mean, const NoiseFilter* after,
                              JobContext& context) const override;
  // What the grid gather (grid/grid_hit_radiance.h) continues paths with.
  const PathTraceSettings& settings() const { return settings_; }
  const DirectLight& direct() const { return direct_; }

 private:
  const DirectLight& direct_;
  PathTraceSettings settings_;
};

class PathTraceSolver : public Solver {
 public:
  static const std::vector<SettingSpec>& setting_specs();
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;
};

}  // namespace bakegi
