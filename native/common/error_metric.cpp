#include "error_metric.h"

#include <cmath>
#include <vector>

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

namespace {

double luminance_at(const float* rgb, size_t i) {
  return kLuminanceWeights[0] * double(rgb[3 * i]) + kLuminanceWeights[1] * double(rgb[3 * i + 1]) +
         kLuminanceWeights[2] * double(rgb[3 * i + 2]);
}

}  // namespace

std::optional<ErrorMetrics> error_metrics(const float* values, const float* reference,
                                          size_t count) {
  const std::optional<double> relative = relative_rmse_luminance(values, reference, count);
  if (!relative) return std::nullopt;
  std::vector<double> y(count), r(count);
  double mean_reference = 0.0, squares = 0.0;
  for (size_t i = 0; i < count; ++i) {
    y[i] = luminance_at(values, i);
    r[i] = luminance_at(reference, i);
    mean_reference += r[i];
    squares += (y[i] - r[i]) * (y[i] - r[i]);
  }
  mean_reference /= double(count);
  if (!(mean_reference > 0.0)) return std::nullopt;
  double weighted = 0.0, lit_sum = 0.0;
  for (size_t i = 0; i < count; ++i) {
    if (!(r[i] > 0.01 * mean_reference)) continue;
    weighted += (y[i] - r[i]) * (y[i] - r[i]) / r[i];
    lit_sum += r[i];
  }
  ErrorMetrics metrics;
  metrics.relative_rmse = *relative;
  metrics.nrmse = std::sqrt(squares / double(count)) / mean_reference;
  metrics.weighted_relative_rmse = std::sqrt(weighted / lit_sum);
  return metrics;
}

}  // namespace bakegi
