// Denoising a Monte Carlo bake over its points (issue 15, item 7; setting "denoise"): an
// edge-aware, noise-aware filter over each point's nearest neighbours, for vertex colours
// and lightmap texels alike (both are bake points: position, normal).
//
// Point i (luminance y_i, variance of its mean v_i from its own samples) becomes the weighted
// mean of its kNeighbours nearest points j (itself included, weight 1), with
//   w_ij = exp(-d_ij² / (2 h_i²))            distance; h_i = distance to its kNeighbours/2-th
//                                            nearest point (follows the points' density)
//        · [n_i·n_j ≥ kMinNormalCosine]      the same side of the same surface...
//        · [|(x_j - x_i)·n_i| ≤ kMaxPlaneSlope d_ij]   ...not a step or a parallel surface
//        · [the two points see each other]   not across a wall (one shadow ray)
//        · exp(-max(0, (y_i - y_j)² - (v_i + v_j)) / (kRangeStrength² (v_i + v_j)))
// The last factor is the noise-aware range kernel of non-local means with the noise's share
// of the difference taken out (Rousselle, Knaus and Zwicker 2012): a difference the noise
// explains costs little, one well beyond it (a shadow edge, a gradient) shuts the neighbour
// out, and where the points have no noise (v = 0) nothing is mixed.
//
// The weighted fit of a plane (bake/local_linear_fit.h) over those weights cuts the peaks of
// curved light; the residual y - f, smoothed by the same weights twice more, is added back
// in the share its energy stands above its noise (twicing with a James-Stein weight: the
// default bake of a closed room 3.6% dark before, about 2% after).
//
// The noise after filtering is predicted for the filter as a whole with the weights taken as
// fixed, scaled by how much noise its residuals show (DenoiseStatistics::variance_scale: the
// samples' variances overstate it); its bias is measured by filtering noisy copies of its
// own output (DenoiseStatistics::local_bias). The bake's error probes (bake/error_estimate.h)
// compare the filtered values with the path tracer and measure both.
//
// The neighbourhoods (nearest points, the surface tests, the visibility rays) depend on the
// points only and are found once; filtering and predicting its noise (for an adaptive
// sampler that aims at the noise left after the filter, field/noise_filter.h) reuse them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "field/noise_filter.h"
#include "scene/bake_points.h"

namespace bakegi {

class JobContext;
class RayTracer;
struct KernelRows;

// Luminances through the filter: the plane fit (passes 1-2) and its smoothed residual.
struct FilteredLuminances {
  std::vector<float> plane;
  std::vector<float> correction;
};

struct DenoiseStatistics {
  // sqrt(mean v_i) / mean y_i, the NRMSE the noise alone would give as the variances say it.
  double noise_before = 0.0;
  // The same for the filtered values as their noise really is: the filter's noise for the
  // weights taken as fixed, times sqrt(variance_scale).
  double noise_after = 0.0;
  // The filter's residuals' energy over what the variances predict for it, in
  // [kMinVarianceScale, 1]: the means of Owen-scrambled samples vary less than their sample
  // variances say (0.54-0.75 of it measured on the suite), so noise_before overstates the
  // raw noise by 1 / sqrt(variance_scale).
  double variance_scale = 1.0;
  // |mean f_i - mean y_i| / mean y_i: how far the filter moved the mean, a part of its bias
  // that can be measured (the raw mean is unbiased and, over all points, nearly noise-free).
  // Path-traced noise is heavy-tailed: the range kernel shuts out a neighbour's rare bright
  // sample more often than a dark one, so the filtered mean falls (measured 1-3%).
  double mean_shift = 0.0;
  // The root mean square of the filter's bias over the points, relative to the mean y,
  // measured on noisy copies of the filtered values (a parametric bootstrap, point_denoiser.cpp):
  // the copies' filtered mean minus the values they were made from, the range kernel's
  // answer to the noise included. On the suite's default bakes it read 0.83-1.2 times the
  // bias measured between filtered and raw means over seeds (docs/benchmarks.md, 0q).
  double local_bias = 0.0;
  // The share of the smoothed residual put back, in [0, 1] (point_denoiser.cpp, pass 3).
  double residual_share = 0.0;
  uint64_t rays = 0;  // visibility rays between neighbours
};

inline constexpr int kDenoiseNeighbours = 32;
inline constexpr float kMinNormalCosine = 0.9f;  // 25.8°
inline constexpr float kMaxPlaneSlope = 0.25f;
inline constexpr float kRangeStrength = 1.0f;
// What the filter holds per point at its peak (the R-tree's entry and nodes while the
// neighbourhoods are found; kDenoiseNeighbours neighbour indices; luminance, guide, filtered
// value and variance; the squared bias, and the bake's copy of the raw values; the second
// pass's kernel, a float per neighbour; the residual correction's and the noise probes'
// vectors; the bias's noisy copy with its own kernel, filtered values and sums; the copy of
// the measured values and variances kept for the final filter), for the job's memory estimate.
inline constexpr size_t kDenoiseBytesPerPoint = 64 + 4 * kDenoiseNeighbours + 48 + 4 + 12 +
                                                4 * kDenoiseNeighbours + 48 + 32 +
                                                4 * kDenoiseNeighbours + 32 + 16;

class PointDenoiser : public NoiseFilter {
 public:
  // Finds each point's admissible neighbours: parallel (TBB), cancellable (Error(CANCELLED)
  // through the context), progress over the context's stage unless `report_progress` is
  // false. `points` must outlive it.
  PointDenoiser(const BakePoints& points, const RayTracer& tracer, float ray_epsilon,
                JobContext& context, bool report_progress = true);

  // Filters `values` in place (one per point; `variance_of_mean` likewise). Cancellable
  // (`values` then unchanged). The statistics' rays are those of the constructor.
  DenoiseStatistics filter(std::span<glm::vec3> values, std::span<const float> variance_of_mean,
                           JobContext& context) const;

  // noise_after / noise_before and the larger of the mean shift and the local bias (as its
  // bias) of filter() (noise left 1 where there is no noise), values unchanged.
  FilteredNoise predict(std::span<const glm::vec3> values, std::span<const float> variance_of_mean,
                        JobContext& context) const override;

  // How much the variances overstate the noise of these values, without filtering them:
  // DenoiseStatistics::variance_scale as filter() would find it (the energy of the filter's
  // residuals over what the variances predict for it), without the bias's noisy copies. For
  // bakes that keep their raw means: the means of Owen-scrambled samples vary less than
  // their sample variances say.
  double noise_scale(std::span<const glm::vec3> values, std::span<const float> variance_of_mean,
                     JobContext& context) const;

  uint64_t rays() const { return rays_; }

 private:
  // What the filter measured on one set of values: its second pass's kernel, the residual's
  // share and the statistics. Kept from the sampler's last prediction, so that filter() on
  // the very same values and variances (the bake ends on them) does not measure them again.
  struct Measurement {
    std::vector<glm::vec3> values;
    std::vector<float> variance_of_mean;
    std::vector<float> kernel_weights;  // kDenoiseNeighbours per point
    float share = 0.0f;
    DenoiseStatistics statistics;
  };
  Measurement measure(std::span<const glm::vec3> values, std::span<const float> variance_of_mean,
                      JobContext& context, bool report_progress) const;

  // The filter's passes over the values' luminance, the noise of its parts from random probes
  // (weights fixed), the residual's share and the noise's scale: what measure() and
  // noise_scale() share. `kernel_weights` gets the second pass's kernel.
  struct ScaledFilter {
    std::vector<float> luminances;
    FilteredLuminances result;
    std::vector<float> plane_variance, correction_variance, covariance;  // per point
    float share = 0.0f;
    double variance_scale = 1.0;
  };
  ScaledFilter filter_and_scale(std::span<const glm::vec3> values,
                                std::span<const float> variance_of_mean,
                                std::vector<float>& kernel_weights, JobContext& context,
                                bool report_progress) const;

  // Filters into `filtered` (may be null: only the statistics) and returns the statistics;
  // measures the values unless the last call measured the same.
  DenoiseStatistics run(std::span<const glm::vec3> values, std::span<const float> variance_of_mean,
                        std::vector<glm::vec3>* filtered, JobContext& context,
                        bool report_progress) const;

  // Passes 1-3 over luminances (point_denoiser.cpp), unclamped; `rows` gets the second
  // pass's kernel. Progress up to `progress_to` (none at 0).
  FilteredLuminances filter_luminances(const std::vector<float>& luminances,
                                       std::span<const float> variance_of_mean, KernelRows& rows,
                                       JobContext& context, double progress_to) const;

  std::span<const uint32_t> admissible(size_t i) const {
    return {neighbours_.data() + i * kDenoiseNeighbours, neighbour_count_[i]};
  }

  const BakePoints& points_;
  // Point i's admissible neighbours, nearest first (i among them), are the first
  // neighbour_count_[i] of neighbours_[i * kDenoiseNeighbours ...].
  std::vector<uint8_t> neighbour_count_;
  std::vector<uint32_t> neighbours_;
  std::vector<float> bandwidth_squared_;  // h_i²
  uint64_t rays_ = 0;
  mutable std::optional<Measurement> last_;
};

// PointDenoiser(points, ...).filter(values, ...): one filtering pass.
DenoiseStatistics denoise_points(const BakePoints& points, std::span<glm::vec3> values,
                                 std::span<const float> variance_of_mean,
                                 const RayTracer& tracer, float ray_epsilon, JobContext& context);

}  // namespace bakegi
