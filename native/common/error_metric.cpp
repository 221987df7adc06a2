#include "error_metric.h"

#include <cmath>

namespace bakegi {

std::optional<double> relative_rmse_luminance(const float* values, const float* reference,
                                              size_t count) {
  if (count == 0) return std::nullopt;
  // Sums in double: a million points of float32 squares would otherwise lose digits.
  double difference_sum = 0.0;
  double reference_sum = 0.0;
  for (size_t i = 0; i < 3 * count; ++i) {
    const double v = values[i];
    const double r = reference[i];
    if (!std::isfinite(v) || !std::isfinite(r)) return std::nullopt;
    const double w = kLuminanceWeights[i % 3];
    difference_sum += w * (v - r) * (v - r);
    reference_sum += w * r * r;
  }
  if (!(reference_sum > 0.0)) return std::nullopt;
  return std::sqrt(difference_sum / reference_sum);
}

}  // namespace bakegi
