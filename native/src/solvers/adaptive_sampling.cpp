#include "solvers/adaptive_sampling.h"

#include <algorithm>
#include <cmath>

namespace bakegi {

SamplingRound plan_sampling_round(std::span<const PointTally> tallies, double target_error,
                                  int64_t max_samples) {
  SamplingRound round;
  const size_t count = tallies.size();
  round.added.assign(count, 0);
  if (count == 0) return round;

  double mean_value = 0.0, mean_variance = 0.0;
  for (const PointTally& t : tallies) {
    if (t.samples > 0) mean_value += t.luminance_sum / double(t.samples);
    mean_variance += luminance_sample_variance(t);
  }
  mean_value /= double(count);
  mean_variance /= double(count);

  // Shrunk variances, their root mean (for c) and the predicted squared error.
  std::vector<double> variance(count);
  double mean_root = 0.0, mean_error_squared = 0.0;
  for (size_t i = 0; i < count; ++i) {
    const PointTally& t = tallies[i];
    const double own_weight = std::max(0.0, double(t.samples) - 1.0);
    variance[i] =
        (own_weight * luminance_sample_variance(t) + kPriorSamples * mean_variance) /
        (own_weight + kPriorSamples);
    mean_root += std::sqrt(variance[i]);
    if (t.samples > 0) mean_error_squared += variance[i] / double(t.samples);
  }
  mean_root /= double(count);
  mean_error_squared /= double(count);
  // No light at all: nothing to measure the error against, and nothing to gain.
  if (!(mean_value > 0.0)) return round;
  round.predicted_error = std::sqrt(mean_error_squared) / mean_value;
  if (round.predicted_error <= target_error) return round;

  const double scale = target_error * mean_value;
  const double c = mean_root / (scale * scale);
  for (size_t i = 0; i < count; ++i) {
    const PointTally& t = tallies[i];
    const double wanted = c * std::sqrt(variance[i]);
    if (t.samples < max_samples && double(t.samples) < wanted) {
      // Up to the wanted count, but at most doubling, so that the variances are measured
      // again before a point gets many more samples on a young estimate.
      const int64_t wanted_count = int64_t(std::min(std::ceil(wanted), double(max_samples)));
      const int64_t added = std::min({wanted_count - t.samples, std::max<int64_t>(t.samples, 1),
                                      max_samples - t.samples});
      round.added[i] = added;
      round.added_samples += added;
    }
  }
  return round;
}

}  // namespace bakegi
