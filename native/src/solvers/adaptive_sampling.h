// Adaptive sampling to a target error (issue 15): a sampling bake spends its samples where
// the noise is and stops when the noise it predicts reaches the target.
//
// The bake's error is measured as NRMSE = sqrt(mean_i (y_i - r_i)^2) / mean_i r_i on
// luminance. The mean of n_i independent samples of variance v_i has E[(y_i - r_i)^2] =
// v_i / n_i, so the tallies predict
//     E = sqrt(mean_i v_i / n_i) / mean_i y_i.
// For a fixed total of samples, sum_i v_i / n_i is smallest with n_i proportional to
// sqrt(v_i); the n_i that reach E = target with that shape are
//     n_i* = c sqrt(v_i),  c = mean_i sqrt(v_i) / (target * mean_i y_i)^2.
// Rounds raise every point still under its n_i* towards it, by at most as many samples as it
// has (the variances are measured again before a point gets far more samples on a young
// estimate), until the prediction meets the target or the points reach the cap.
//
// A point's variance after few samples is itself noisy (a dark point that has not yet met a
// rare bright path reports 0), so it is shrunk towards the mean variance of all points with
// the weight of kPriorSamples samples. With quasi-random samples the true error falls faster
// than v_i / n_i, so the prediction is an upper bound and the bake stops late, not early
// (through the denoiser the filter's residuals measure by how much and the rounds aim at the
// noise as it is: bake/point_denoiser.h, DenoiseStatistics::variance_scale).
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace bakegi {

// One point's samples so far (luminance only: the error metric's quantity).
struct PointTally {
  int64_t samples = 0;
  double luminance_sum = 0.0;
  double luminance_squares = 0.0;
};

struct SamplingRound {
  double predicted_error = 0.0;  // E above, from the tallies as they are
  std::vector<int64_t> added;    // per point: samples the next round adds
  int64_t added_samples = 0;     // the next round's samples in all
  bool done() const { return added_samples == 0; }
};

inline constexpr double kPriorSamples = 4.0;

// The sample variance s^2 of a point's luminance samples (0 below two samples).
inline double luminance_sample_variance(const PointTally& tally) {
  if (tally.samples < 2) return 0.0;
  const double n = double(tally.samples);
  const double mean = tally.luminance_sum / n;
  return std::max(0.0, (tally.luminance_squares - n * mean * mean) / (n - 1.0));
}

// The variance of a point's mean luminance: s^2 / n.
inline double luminance_variance_of_mean(const PointTally& tally) {
  return tally.samples > 0 ? luminance_sample_variance(tally) / double(tally.samples) : 0.0;
}
// The prediction E of the tallies, and the samples each point adds next (none once E <=
// target or every point that wants more has reached max_samples). Points with 0 samples count as
// needing a first round (callers start with one).
SamplingRound plan_sampling_round(std::span<const PointTally> tallies, double target_error,
                                  int64_t max_samples);

}  // namespace bakegi
