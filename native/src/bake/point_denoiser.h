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
// The noise after filtering is predicted as Σ_j w_ij² v_j / (Σ_j w_ij)² (weights taken as
// fixed). The bias the filter adds is not predicted: the bake's error probes
// (bake/error_estimate.h) compare the filtered values with the path tracer and measure it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "scene/bake_points.h"

namespace bakegi {

class JobContext;
class RayTracer;

struct DenoiseStatistics {
  // sqrt(mean v_i) / mean y_i before and after (the NRMSE the noise alone would give).
  double noise_before = 0.0;
  double noise_after = 0.0;
  uint64_t rays = 0;  // visibility rays between neighbours
};

inline constexpr int kDenoiseNeighbours = 32;
inline constexpr float kMinNormalCosine = 0.9f;  // 25.8°
inline constexpr float kMaxPlaneSlope = 0.25f;
inline constexpr float kRangeStrength = 1.0f;
// What the filter holds per point at its peak (the R-tree's entry and nodes, luminance,
// variance, neighbour mask, guide plane, filtered value), for the job's memory estimate.
inline constexpr size_t kDenoiseBytesPerPoint = 96;

// Filters `values` in place (one per point; `variance_of_mean` likewise). Parallel (TBB),
// cancellable (Error(CANCELLED) through the context, `values` then unchanged).
DenoiseStatistics denoise_points(const BakePoints& points, std::span<glm::vec3> values,
                                 std::span<const float> variance_of_mean,
                                 const RayTracer& tracer, float ray_epsilon, JobContext& context);

}  // namespace bakegi
