// The error of a bake against a reference, one implementation for the CLI and the tests
// (Python scripts call the CLI or tools/real_scene_metrics.py, which computes the same).
//
// The project's two metrics (README, "Standards"), on luminance y = 0.2126 R + 0.7152 G +
// 0.0722 B of values and r of the reference:
//   NRMSE                       sqrt(mean((y - r)^2)) / mean(r)
//   weighted relative RMSE      sqrt(sum((y - r)^2 / r) / sum(r)) over the points with
//                               r > 1% of mean(r) (where the reference sees light)
// (error_metrics()), and the older one the sweeps of docs/benchmarks.md sections 1-2 were
// measured with, a relative RMSE with per-channel luminance weights,
//   e = sqrt( sum_i sum_c w_c (v_ic - r_ic)^2  /  sum_i sum_c w_c r_ic^2 )
// (relative_rmse_luminance()).
//
// with Rec. 709 luminance weights w = (0.2126, 0.7152, 0.0722). Weighting the squared
// differences per channel (rather than comparing luminances) keeps chroma errors visible
// while letting green, which the eye sees best, count most. e = 0.01 reads as "1% RMS".
// The CLI (`bakegi sweep`, `bakegi compare`) and the tests use this function; Python
// scripts call the CLI instead of re-implementing it.
#pragma once

#include <cstddef>
#include <optional>

namespace bakegi {

inline constexpr float kLuminanceWeights[3] = {0.2126f, 0.7152f, 0.0722f};

// values and reference hold 3 * count floats (RGB per bake point). Returns nullopt when
// the error is undefined: count == 0, a non-finite entry, or a reference that is zero
// everywhere.
std::optional<double> relative_rmse_luminance(const float* values, const float* reference,
                                              size_t count);

struct ErrorMetrics {
  double nrmse = 0.0;
  double weighted_relative_rmse = 0.0;
  double relative_rmse = 0.0;  // relative_rmse_luminance
};

// All three; nullopt where relative_rmse_luminance is undefined or the reference's mean
// luminance is not positive.
std::optional<ErrorMetrics> error_metrics(const float* values, const float* reference,
                                          size_t count);

}  // namespace bakegi
