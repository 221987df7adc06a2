// The path tracer with a solver's solution as control variate (controlled_path.h), as an
// indirect field: what antiradiance returns with "residual" = "path_traced". Unbiased like
// the path tracer and sampled with its settings (samples, seed, target_error, max_bounces).
//
// Before the bake a pilot measures, on up to kPilotPoints bake points spread over the list,
// how much of the path's variance the cache removes, and picks the probability q with which
// a path goes on beyond its first light sample (ResidualStatistics::best_rest_probability),
// unless "residual_fraction" fixes it. The report says what was measured:
// residual_path_spread, residual_spread (per-sample relative spreads), residual_fraction (q).
#pragma once

#include <memory>

#include "solvers/pathtrace/path_trace_solver.h"

namespace bakegi {

class DirectLight;
class RadianceCache;

class ControlledPathField : public SampledField {
 public:
  static constexpr size_t kPilotPoints = 256;
  static constexpr int kPilotSamples = 32;
  // No path goes on less often than this: it bounds the weight 1/q of a residual that the
  // pilot did not see.
  static constexpr double kMinRestProbability = 0.05;

  // `direct` (and its scene and tracer) must outlive the field. rest_probability in (0, 1],
  // or 0 for the pilot's choice.
  ControlledPathField(const DirectLight& direct, std::shared_ptr<const RadianceCache> cache,
                      const PathTraceSettings& settings, double rest_probability);
  bool evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                              std::span<float> variance_of_mean, const NoiseFilter* after,
                              JobContext& context) const override;

 private:
  double pilot(const BakePoints& points, JobContext& context) const;

  const DirectLight& direct_;
  std::shared_ptr<const RadianceCache> cache_;
  PathTraceSettings settings_;
  double rest_probability_;
};

}  // namespace bakegi
