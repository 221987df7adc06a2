#include "bake/point_denoiser.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iterator>
#include <numbers>
#include <utility>
#include <vector>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "bake/local_linear_fit.h"
#include "scene/mutual_visibility.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/luminance.h"
#include "util/pcg32.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using TreePoint = bg::model::point<float, 3, bg::cs::cartesian>;
using Entry = std::pair<TreePoint, uint32_t>;
using Tree = bgi::rtree<Entry, bgi::quadratic<16>>;

TreePoint tree_point(const glm::vec3& p) { return TreePoint(p.x, p.y, p.z); }

constexpr size_t kPointsPerBlock = 64;
// A guide plane whose weighted squared residuals exceed this many times the samples' noise
// variance is not a plane (a step, a shadow edge): its slope is not used.
constexpr double kPlaneFitTolerance = 2.0;
// The residual correction smooths the filter's residual this many times (pass 3, below).
constexpr int kResidualPasses = 2;
// Probes of the filter's noise: enough that count × probes reaches this (at least 4).
constexpr size_t kProbeSamples = 32768;
// Noisy copies the filter's bias is measured on: enough that count × copies reaches this,
// between kMinBiasReplicas and kMaxBiasReplicas (each costs a pass over all points).
constexpr size_t kBiasReplicaSamples = 8192;
constexpr size_t kMinBiasReplicas = 2;
constexpr size_t kMaxBiasReplicas = 4;
// The residuals may show less noise than the samples' variances say (quasi-random samples),
// never more; this keeps the scale off 0 where almost nothing is filtered.
constexpr double kMinVarianceScale = 0.05;

struct Neighbour {
  uint32_t index;
  float distance_squared;
};

static_assert(kDenoiseNeighbours <= 64, "the admissible neighbours are a 64-bit mask");

// The kDenoiseNeighbours nearest points of i (i among them), nearest first, and h_i².
float nearest_points(const Tree& tree, const BakePoints& points, size_t i,
                     std::vector<Entry>& found, std::vector<Neighbour>& near) {
  const glm::vec3& x = points.positions[i];
  found.clear();
  tree.query(bgi::nearest(tree_point(x), unsigned(kDenoiseNeighbours)), std::back_inserter(found));
  near.clear();
  for (const Entry& e : found) {
    const glm::vec3 d = points.positions[e.second] - x;
    near.push_back({e.second, glm::dot(d, d)});
  }
  std::sort(near.begin(), near.end(), [](const Neighbour& a, const Neighbour& b) {
    return a.distance_squared < b.distance_squared ||
           (a.distance_squared == b.distance_squared && a.index < b.index);
  });
  if (near.empty()) return 0.0f;
  return near[std::min(near.size() - 1, size_t(kDenoiseNeighbours / 2))].distance_squared;
}

float spatial_weight(const Neighbour& neighbour, float h2) {
  return h2 > 0.0f ? std::exp(-neighbour.distance_squared / (2.0f * h2)) : 0.0f;
}

// Parallel over blocks of points, cancellable, progress from `from` to `to` (none when
// `from` == `to`).
template <typename PerPoint>
void for_each_point(size_t count, JobContext& context, double from, double to,
                    PerPoint per_point) {
  std::atomic<size_t> done{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kPointsPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      context.throw_if_cancelled();
                      for (size_t i = block.begin(); i != block.end(); ++i) per_point(i);
                      if (from == to) return;
                      const size_t now = done.fetch_add(block.size()) + block.size();
                      context.set_stage_progress(from + (to - from) * double(now) /
                                                            double(count));
                    });
}

}  // namespace

// The second pass's kernel, one sparse row per point: k_ij for i's admissible neighbours j,
// in the order PointDenoiser holds them (a neighbour the pass leaves out has weight 0), so
// that it can be applied again.
struct KernelRows {
  std::span<const uint32_t> neighbours;  // kDenoiseNeighbours per point
  std::span<const uint8_t> counts;
  std::vector<float>& weights;  // as many as neighbours

  KernelRows(std::span<const uint32_t> neighbours, std::span<const uint8_t> counts,
             std::vector<float>& weights)
      : neighbours(neighbours), counts(counts), weights(weights) {}

  // (K x)_i.
  template <typename T>
  T apply_row(size_t i, const std::vector<T>& x) const {
    T sum(0.0f);
    for (size_t m = 0; m < counts[i]; ++m) {
      sum += weights[i * kDenoiseNeighbours + m] * x[neighbours[i * kDenoiseNeighbours + m]];
    }
    return sum;
  }
};

namespace {

// The residual correction: K^kResidualPasses (x - K x) for the filtered K x, applied as
// kResidualPasses products with K (rows in parallel, cancellable).
template <typename T>
std::vector<T> residual_correction(const KernelRows& rows, const std::vector<T>& x,
                                   const std::vector<T>& filtered, JobContext& context) {
  const size_t count = x.size();
  std::vector<T> residual(count), next(count);
  for (size_t i = 0; i < count; ++i) residual[i] = x[i] - filtered[i];
  for (int pass = 0; pass < kResidualPasses; ++pass) {
    for_each_point(count, context, 0.0, 0.0,
                   [&](size_t i) { next[i] = rows.apply_row(i, residual); });
    residual.swap(next);
  }
  return residual;
}

// Random signs ±1 of probe r at point j, the same on every run.
float probe_sign(size_t j, size_t r) {
  return (mix64(mix64(uint64_t(j)) ^ (uint64_t(r) * 0x9E3779B97F4A7C15ull)) & 1) ? 1.0f : -1.0f;
}

// A standard normal number for point j of noisy copy r, the same on every run (Box-Muller
// from two hashed uniforms).
double replica_normal(size_t j, size_t r) {
  const uint64_t a = mix64(mix64(uint64_t(j) ^ 0xA0761D6478BD642Full) ^
                           ((uint64_t(r) + 1) * 0xD1B54A32D192ED03ull));
  const uint64_t b = mix64(a ^ 0x8EBC6AF09C88C6E3ull);
  const double u1 = (double(a >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = double(b >> 11) * 0x1.0p-53;          // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

// Point i of the filter's output before clamping: the plane plus the residual's share.
float filtered_luminance(const FilteredLuminances& f, size_t i, float share) {
  return f.plane[i] + share * f.correction[i];
}

// One value and one variance per point, or an internal error.
void check_one_per_point(size_t points, size_t values, size_t variances) {
  if (values != points || variances != points) {
    throw Error(BAKEGI_ERROR_INTERNAL, "denoise: one value and one variance per point expected");
  }
}

// Whether `a` and `b` hold the same numbers, bit for bit.
template <typename T>
bool same_bits(std::span<const T> a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

// Var(a + s c) from Var a, Cov(a, c) and Var c.
double variance_of_sum(double a, double covariance, double c, double share) {
  return a + 2.0 * share * covariance + share * share * c;
}

}  // namespace

PointDenoiser::PointDenoiser(const BakePoints& points, const RayTracer& tracer,
                             float ray_epsilon, JobContext& context, bool report_progress)
    : points_(points) {
  const size_t count = points.size();
  neighbour_count_.assign(count, 0);
  neighbours_.assign(count * kDenoiseNeighbours, 0);
  bandwidth_squared_.assign(count, 0.0f);
  if (count == 0) return;

  std::vector<Entry> entries(count);
  for (size_t i = 0; i < count; ++i) entries[i] = {tree_point(points.positions[i]), uint32_t(i)};
  const Tree tree(entries.begin(), entries.end());  // packed: built in one pass
  std::vector<Entry>().swap(entries);

  // Which neighbours lie on the same surface in sight of the point.
  std::atomic<uint64_t> rays{0};
  tbb::enumerable_thread_specific<std::pair<std::vector<Entry>, std::vector<Neighbour>>> scratch;
  for_each_point(count, context, 0.0, report_progress ? 1.0 : 0.0, [&](size_t i) {
    auto& [found, near] = scratch.local();
    const float h2 = nearest_points(tree, points, i, found, near);
    const glm::vec3& x = points.positions[i];
    const glm::vec3& n = points.normals[i];
    uint64_t traced = 0;
    size_t kept = 0;
    for (const Neighbour& neighbour : near) {
      const uint32_t j = neighbour.index;
      if (j != i) {
        if (!(spatial_weight(neighbour, h2) > 1e-4f)) continue;
        const glm::vec3& nj = points.normals[j];
        if (!(glm::dot(n, nj) >= kMinNormalCosine)) continue;
        const glm::vec3 d = points.positions[j] - x;
        if (std::abs(glm::dot(d, n)) > kMaxPlaneSlope * std::sqrt(neighbour.distance_squared)) {
          continue;
        }
        ++traced;
        if (!points_see_each_other(tracer, x, n, points.positions[j], nj, ray_epsilon)) continue;
      }
      neighbours_[i * kDenoiseNeighbours + kept] = j;
      ++kept;
    }
    neighbour_count_[i] = uint8_t(kept);
    bandwidth_squared_[i] = h2;
    rays.fetch_add(traced, std::memory_order_relaxed);
  });
  rays_ = rays.load();
}

FilteredLuminances PointDenoiser::filter_luminances(const std::vector<float>& luminances,
                                                    std::span<const float> variance_of_mean,
                                                    KernelRows& rows, JobContext& context,
                                                    double progress_to) const {
  const size_t count = points_.size();
  // Point i's admissible neighbour j: its weight by distance, and its offset in units of h_i
  // in i's tangent frame.
  const auto distance_weight = [&](size_t i, uint32_t j) {
    const glm::vec3 d = points_.positions[j] - points_.positions[i];
    return spatial_weight({j, glm::dot(d, d)}, bandwidth_squared_[i]);
  };
  const auto offset_of = [&](size_t i, const Frame& frame, uint32_t j) {
    const float h2 = bandwidth_squared_[i];
    const float inverse_h = h2 > 0.0f ? 1.0f / std::sqrt(h2) : 0.0f;
    const glm::vec3 d = points_.positions[j] - points_.positions[i];
    return inverse_h * glm::vec2(glm::dot(d, frame.tangent), glm::dot(d, frame.bitangent));
  };

  // Pass 1: the guide, the spatially weighted local linear fit g_i of the admissible
  // neighbours' luminance with its variance. The range kernel compares neighbours with g_i,
  // not with y_i: against a noisy centre it would favour the neighbours that share y_i's noise
  // (measured: the filtered noise 2x the prediction on a flat floor).
  std::vector<float> guide(count), guide_variance(count);
  std::vector<glm::vec2> guide_slope(count);  // per unit of offset / h_i, in i's tangent frame
  // One point's admissible neighbours as a pass weighs them, and their fitted kernel.
  struct Scratch {
    std::vector<float> weights;
    std::vector<glm::vec2> offsets;
    std::vector<uint32_t> members;
    std::vector<double> kernel;
    std::vector<glm::dvec2> slope_kernel;

    void add(float weight, const glm::vec2& offset, uint32_t member) {
      weights.push_back(weight);
      offsets.push_back(offset);
      members.push_back(member);
    }
    void clear() {
      weights.clear();
      offsets.clear();
      members.clear();
    }
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  for_each_point(count, context, 0.0, 0.5 * progress_to, [&](size_t i) {
    Scratch& s = scratch.local();
    const Frame frame(points_.normals[i]);
    s.clear();
    for (const uint32_t j : admissible(i)) {
      s.add(j == i ? 1.0f : distance_weight(i, j), offset_of(i, frame, j), j);
    }
    local_linear_kernel(s.weights, s.offsets, s.kernel, &s.slope_kernel);
    double value = 0.0, variance = 0.0;
    glm::dvec2 slope(0.0);
    for (size_t m = 0; m < s.members.size(); ++m) {
      value += s.kernel[m] * luminances[s.members[m]];
      slope += s.slope_kernel[m] * double(luminances[s.members[m]]);
      variance += s.kernel[m] * s.kernel[m] * double(variance_of_mean[s.members[m]]);
    }
    // The plane guides the range kernel only where it fits to within the noise: across a
    // step it would pass for a ramp and let the other side in.
    double residual = 0.0, noise = 0.0;
    for (size_t m = 0; m < s.members.size(); ++m) {
      const double r =
          luminances[s.members[m]] - value - glm::dot(slope, glm::dvec2(s.offsets[m]));
      residual += s.weights[m] * r * r;
      noise += s.weights[m] * double(variance_of_mean[s.members[m]]);
    }
    const bool planar = residual <= kPlaneFitTolerance * noise;
    guide[i] = float(value);
    guide_slope[i] = planar ? glm::vec2(slope) : glm::vec2(0.0f);
    guide_variance[i] = float(variance);
  });

  // Pass 2: the admissible neighbours (the point itself included) weighted by distance and
  // by how far their value lies from the guide beyond the noise of both.
  FilteredLuminances result;
  result.plane.resize(count);
  for_each_point(count, context, 0.5 * progress_to, progress_to, [&](size_t i) {
    Scratch& s = scratch.local();
    const Frame frame(points_.normals[i]);
    s.clear();
    for (const uint32_t j : admissible(i)) {
      // The point itself always counts fully: where every neighbour lies far from the guide
      // (at an edge the guide mixes both sides) the point keeps its own value.
      const glm::vec2 offset = offset_of(i, frame, j);
      float w = 1.0f;
      if (j != i) {
        const float noise = guide_variance[i] + variance_of_mean[j];
        if (!(noise > 0.0f)) {  // noise-free: nothing to trade
          s.add(0.0f, offset, j);
          continue;
        }
        // Against the guide's plane at j: against its value at i a gradient would favour the
        // neighbours whose noise leans towards i (measured: a bias at a ramp's rim).
        const float difference = guide[i] + glm::dot(guide_slope[i], offset) - luminances[j];
        const float excess = std::max(0.0f, difference * difference - noise);
        w = distance_weight(i, j);
        // Most neighbours lie within the noise (excess 0, a factor of exactly 1): exp only
        // for the others.
        if (excess > 0.0f) w *= std::exp(-excess / (kRangeStrength * kRangeStrength * noise));
      }
      s.add(w, offset, j);
    }
    local_linear_kernel(s.weights, s.offsets, s.kernel);
    std::copy(s.kernel.begin(), s.kernel.end(), rows.weights.begin() + i * kDenoiseNeighbours);
    double value = 0.0;
    for (size_t m = 0; m < s.members.size(); ++m) {
      value += s.kernel[m] * double(luminances[s.members[m]]);
    }
    result.plane[i] = float(value);
  });

  // Pass 3: the residual's share to put back. Where the light curves across a neighbourhood
  // (it peaks in the middle of a wall, so nearly everywhere in a room) the plane cuts the
  // peak, with one sign over the whole face: the default bake came out 1-4% dark. The
  // residual y - Ky holds that cut plus noise; smoothed by K twice more it keeps the cut
  // (smooth on the scale of the neighbourhood) and loses most of the noise (Tukey's
  // twicing, with the residual smoothed more than once). run() decides how much of it to add.
  result.correction = residual_correction(rows, luminances, result.plane, context);
  return result;
}

PointDenoiser::ScaledFilter PointDenoiser::filter_and_scale(std::span<const glm::vec3> values,
                                                            std::span<const float> variance_of_mean,
                                                            std::vector<float>& kernel_weights,
                                                            JobContext& context,
                                                            bool report_progress) const {
  const size_t count = points_.size();
  ScaledFilter f;
  f.luminances.resize(count);
  for (size_t i = 0; i < count; ++i) f.luminances[i] = float(luminance(values[i]));
  kernel_weights.assign(neighbours_.size(), 0.0f);
  KernelRows rows(neighbours_, neighbour_count_, kernel_weights);
  f.result =
      filter_luminances(f.luminances, variance_of_mean, rows, context, report_progress ? 1.0 : 0.0);
  const FilteredLuminances& result = f.result;
  // The noise, per point, of the plane (K z), of the correction (c(z) = K^p (I - K) z), of
  // the plane's residual (K z - z) and their products, the weights taken as fixed: means over
  // random probes z_j = ±sqrt(v_j) (Hutchinson's estimator). Noisy per point, but only sums
  // over the points are used, with enough probes that they hold on small bakes too.
  const size_t probes = std::clamp<size_t>((kProbeSamples + count - 1) / count, 4, 64);
  f.plane_variance.assign(count, 0.0f);
  f.correction_variance.assign(count, 0.0f);
  f.covariance.assign(count, 0.0f);
  std::vector<float> residual_variance(count, 0.0f), residual_covariance(count, 0.0f), probe(count),
      probe_plane(count);
  for (size_t r = 0; r < probes; ++r) {
    for_each_point(count, context, 0.0, 0.0, [&](size_t j) {
      probe[j] = probe_sign(j, r) * std::sqrt(std::max(0.0f, variance_of_mean[j]));
    });
    for_each_point(count, context, 0.0, 0.0,
                   [&](size_t i) { probe_plane[i] = rows.apply_row(i, probe); });
    const std::vector<float> correction = residual_correction(rows, probe, probe_plane, context);
    for_each_point(count, context, 0.0, 0.0, [&](size_t i) {
      const float residual = probe_plane[i] - probe[i];
      f.plane_variance[i] += probe_plane[i] * probe_plane[i] / float(probes);
      f.correction_variance[i] += correction[i] * correction[i] / float(probes);
      f.covariance[i] += probe_plane[i] * correction[i] / float(probes);
      residual_variance[i] += residual * residual / float(probes);
      residual_covariance[i] += residual * correction[i] / float(probes);
    });
  }
  // How much of the correction to add: s = 1 - (its noise) / (its energy), at least 0 (the
  // positive-part James-Stein weight). Where the points sample the light densely (lightmap
  // texels) the plane cuts nothing and the correction is noise: s near 0 (measured 0.00 and
  // 0.24 on two lightmaps, where adding it all cost 20% more time for the same error); on
  // the corners of coarse meshes it is mostly signal: 0.67-0.91 on the suite's scenes.
  double energy = 0.0, noise_energy = 0.0;
  for (size_t i = 0; i < count; ++i) {
    energy += double(result.correction[i]) * double(result.correction[i]);
    noise_energy += double(f.correction_variance[i]);
  }
  f.share = energy > 0.0 ? float(std::clamp(1.0 - noise_energy / energy, 0.0, 1.0)) : 0.0f;

  // How much noise the values really carry: the filter's residuals f - y against what the
  // variances predict for them. Owen-scrambled samples' means vary less than their sample
  // variance says (measured 0.54-0.75 of it at the suite's points), which the residuals show
  // and the variances cannot; a bias in the residuals only raises the scale (it errs safe).
  double realized = 0.0, predicted = 0.0;
  for (size_t i = 0; i < count; ++i) {
    const double residual =
        double(filtered_luminance(result, i, f.share)) - double(f.luminances[i]);
    realized += residual * residual;
    predicted += variance_of_sum(residual_variance[i], residual_covariance[i],
                                 f.correction_variance[i], f.share);
  }
  f.variance_scale =
      predicted > 0.0 ? std::clamp(realized / predicted, kMinVarianceScale, 1.0) : 1.0;
  return f;
}

PointDenoiser::Measurement PointDenoiser::measure(std::span<const glm::vec3> values,
                                                  std::span<const float> variance_of_mean,
                                                  JobContext& context, bool report_progress) const {
  const size_t count = points_.size();
  Measurement measured;
  DenoiseStatistics& statistics = measured.statistics;
  statistics.rays = rays_;
  const ScaledFilter f =
      filter_and_scale(values, variance_of_mean, measured.kernel_weights, context, report_progress);
  const std::vector<float>& luminances = f.luminances;
  const float share = f.share;
  const double variance_scale = f.variance_scale;
  measured.share = share;
  statistics.residual_share = share;
  statistics.variance_scale = variance_scale;
  std::vector<float> truth(count);
  for (size_t i = 0; i < count; ++i) {
    truth[i] = std::max(0.0f, filtered_luminance(f.result, i, share));
  }

  // The bias, measured on noisy copies of the filtered values (a parametric bootstrap): copy
  // r is f + e_r, e_r Gaussian with the values' noise, filtered again with the same share;
  // the copies' mean minus f is the filter's bias at f, the range kernel's answer to the
  // noise included (what a bias estimate with the weights taken as fixed misses: it read 0
  // where the filter moved the suite's corners by 1-2%). Less the noise of the copies' mean,
  // measured from their spread.
  const size_t replicas = std::clamp<size_t>((kBiasReplicaSamples + count - 1) / count,
                                             kMinBiasReplicas, kMaxBiasReplicas);
  std::vector<double> copy_sum(count, 0.0), copy_squares(count, 0.0);
  std::vector<float> copy(count);
  std::vector<float> copy_weights(neighbours_.size(), 0.0f);
  KernelRows copy_rows(neighbours_, neighbour_count_, copy_weights);  // every copy rewrites it
  for (size_t r = 0; r < replicas; ++r) {
    for_each_point(count, context, 0.0, 0.0, [&](size_t j) {
      const double sigma = std::sqrt(variance_scale * std::max(0.0f, variance_of_mean[j]));
      copy[j] = float(double(truth[j]) + sigma * replica_normal(j, r));
    });
    const FilteredLuminances copy_result =
        filter_luminances(copy, variance_of_mean, copy_rows, context, 0.0);
    for_each_point(count, context, 0.0, 0.0, [&](size_t i) {
      const double value = std::max(0.0f, filtered_luminance(copy_result, i, share));
      copy_sum[i] += value;
      copy_squares[i] += value * value;
    });
  }

  double mean = 0.0, before = 0.0, after = 0.0, filtered_mean = 0.0, bias = 0.0;
  for (size_t i = 0; i < count; ++i) {
    const double copies = double(replicas);
    const double copy_mean = copy_sum[i] / copies;
    const double copy_spread =
        std::max(0.0, copy_squares[i] - copies * copy_mean * copy_mean) / (copies - 1.0);
    const double offset = copy_mean - double(truth[i]);
    bias += offset * offset - copy_spread / copies;
    mean += double(luminances[i]);
    before += double(variance_of_mean[i]);
    after += variance_of_sum(f.plane_variance[i], f.covariance[i], f.correction_variance[i], share);
    filtered_mean += double(truth[i]);
  }
  if (mean > 0.0) {
    const double mean_value = mean / double(count);
    statistics.noise_before = std::sqrt(before / double(count)) / mean_value;
    statistics.noise_after = std::sqrt(variance_scale * after / double(count)) / mean_value;
    statistics.mean_shift = std::abs(filtered_mean - mean) / mean;
    statistics.local_bias = std::sqrt(std::max(0.0, bias / double(count))) / mean_value;
  }
  measured.values.assign(values.begin(), values.end());
  measured.variance_of_mean.assign(variance_of_mean.begin(), variance_of_mean.end());
  return measured;
}

DenoiseStatistics PointDenoiser::run(std::span<const glm::vec3> values,
                                     std::span<const float> variance_of_mean,
                                     std::vector<glm::vec3>* filtered, JobContext& context,
                                     bool report_progress) const {
  const size_t count = points_.size();
  check_one_per_point(count, values.size(), variance_of_mean.size());
  if (count == 0) {
    DenoiseStatistics statistics;
    statistics.rays = rays_;
    return statistics;
  }
  // The sampler's last prediction measured these very values (the bake ends on them): the
  // filter, the noise probes and the noisy copies need not run again.
  const bool measured = last_ && same_bits(values, last_->values) &&
                        same_bits(variance_of_mean, last_->variance_of_mean);
  if (!measured) {
    last_.reset();  // its kernel is not held next to the new one's
    last_ = measure(values, variance_of_mean, context, report_progress);
  }
  if (filtered) {
    // Colour with the weights the luminance chose.
    KernelRows rows(neighbours_, neighbour_count_, last_->kernel_weights);
    const float share = last_->share;
    const std::vector<glm::vec3> raw(values.begin(), values.end());
    filtered->assign(count, glm::vec3(0.0f));
    for_each_point(count, context, 0.0, 0.0,
                   [&](size_t i) { (*filtered)[i] = rows.apply_row(i, raw); });
    const std::vector<glm::vec3> correction = residual_correction(rows, raw, *filtered, context);
    // A slope fitted from noise can extrapolate below zero; light cannot.
    for (size_t i = 0; i < count; ++i) {
      (*filtered)[i] = glm::max((*filtered)[i] + share * correction[i], glm::vec3(0.0f));
    }
  }

  return last_->statistics;
}

double PointDenoiser::noise_scale(std::span<const glm::vec3> values,
                                  std::span<const float> variance_of_mean,
                                  JobContext& context) const {
  check_one_per_point(points_.size(), values.size(), variance_of_mean.size());
  if (values.empty()) return 1.0;
  std::vector<float> kernel_weights;
  return filter_and_scale(values, variance_of_mean, kernel_weights, context, false).variance_scale;
}

DenoiseStatistics PointDenoiser::filter(std::span<glm::vec3> values,
                                        std::span<const float> variance_of_mean,
                                        JobContext& context) const {
  std::vector<glm::vec3> filtered;
  const DenoiseStatistics statistics = run(values, variance_of_mean, &filtered, context, true);
  std::copy(filtered.begin(), filtered.end(), values.begin());
  return statistics;
}

FilteredNoise PointDenoiser::predict(std::span<const glm::vec3> values,
                                     std::span<const float> variance_of_mean,
                                     JobContext& context) const {
  const DenoiseStatistics statistics = run(values, variance_of_mean, nullptr, context, false);
  FilteredNoise predicted;
  if (statistics.noise_before > 0.0) {
    predicted.noise_left = statistics.noise_after / statistics.noise_before;
  }
  predicted.bias = std::max(statistics.mean_shift, statistics.local_bias);
  return predicted;
}

DenoiseStatistics denoise_points(const BakePoints& points, std::span<glm::vec3> values,
                                 std::span<const float> variance_of_mean,
                                 const RayTracer& tracer, float ray_epsilon, JobContext& context) {
  check_one_per_point(points.size(), values.size(), variance_of_mean.size());
  return PointDenoiser(points, tracer, ray_epsilon, context).filter(values, variance_of_mean,
                                                                     context);
}

}  // namespace bakegi
