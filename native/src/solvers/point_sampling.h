// The Monte Carlo loop shared by the sampling solvers: for every bake point, average a
// one-sample estimator over samples [offset, offset + count), each sample with its own
// random stream (util/random.h), so results are bit-identical for any thread count and
// chunks of samples average to one run. The streams begin with Owen-scrambled Sobol' points
// (sobol_sample_stream): the first dimensions of a point's samples are stratified together.
// Parallel over blocks of points with TBB; checks cancel and reports progress every few
// samples; counts rays into the report.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include <glm/glm.hpp>

#include "field/indirect_field.h"
#include "scene/bake_points.h"
#include "lights/surface_point.h"

namespace bakegi {

class JobContext;
class RandomStream;
class Settings;

struct SampleSettings {
  int64_t samples = 64;
  int64_t seed = 0;
  int64_t sample_offset = 0;
  // > 0: sample adaptively until the predicted NRMSE reaches it, `samples` per point at
  // most (solvers/adaptive_sampling.h); 0: exactly `samples` per point.
  double target_error = 0.0;

  // Reads "samples", "seed", "sample_offset" and "target_error" with their ranges.
  static SampleSettings from(const Settings& settings);
};

// One sample of a quantity at a surface point; adds the rays it traced to `rays`.
using PointSampleEstimator =
    std::function<glm::vec3(const SurfacePoint& point, RandomStream& rng, uint64_t& rays)>;

// `variance_of_mean`, when not empty (one per point), receives each point's variance of its
// result's luminance as its samples' spread estimates it (luminance_variance_of_mean).
// `after`: the filter the result will go through (field/noise_filter.h); with a target error
// the rounds stop when the noise left after it, not the raw noise, meets the target.
void estimate_at_points(const BakePoints& points, std::span<glm::vec3> out,
                        const SampleSettings& sampling, const PointSampleEstimator& estimator,
                        JobContext& context, std::span<float> variance_of_mean = {},
                        const NoiseFilter* after = nullptr);

// A field that samples (estimate_at_points): it always knows its noise, so evaluate() is
// evaluate_with_variance() without the variances.
class SampledField : public IndirectField {
 public:
  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const final {
    evaluate_with_variance(points, out, {}, nullptr, context);
  }
};

}  // namespace bakegi
