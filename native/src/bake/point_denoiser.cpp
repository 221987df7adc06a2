#include "bake/point_denoiser.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <utility>
#include <vector>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bake/local_linear_fit.h"
#include "scene/mutual_visibility.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/luminance.h"
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

// Parallel over blocks of points, cancellable, progress from `from` to `to`.
template <typename PerPoint>
void for_each_point(size_t count, JobContext& context, double from, double to,
                    PerPoint per_point) {
  std::atomic<size_t> done{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kPointsPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      context.throw_if_cancelled();
                      std::vector<Entry> found;
                      std::vector<Neighbour> near;
                      for (size_t i = block.begin(); i != block.end(); ++i) {
                        per_point(i, found, near);
                      }
                      const size_t now = done.fetch_add(block.size()) + block.size();
                      context.set_stage_progress(from + (to - from) * double(now) /
                                                            double(count));
                    });
}

}  // namespace

DenoiseStatistics denoise_points(const BakePoints& points, std::span<glm::vec3> values,
                                 std::span<const float> variance_of_mean,
                                 const RayTracer& tracer, float ray_epsilon, JobContext& context) {
  const size_t count = points.size();
  if (values.size() != count || variance_of_mean.size() != count) {
    throw Error(BAKEGI_ERROR_INTERNAL, "denoise: one value and one variance per point expected");
  }
  DenoiseStatistics statistics;
  if (count == 0) return statistics;

  std::vector<Entry> entries(count);
  for (size_t i = 0; i < count; ++i) entries[i] = {tree_point(points.positions[i]), uint32_t(i)};
  const Tree tree(entries.begin(), entries.end());  // packed: built in one pass
  std::vector<Entry>().swap(entries);

  std::vector<float> luminances(count);
  for (size_t i = 0; i < count; ++i) luminances[i] = float(luminance(values[i]));

  // Pass 1: which neighbours lie on the same surface in sight of the point (a bit per
  // neighbour, in nearest_points' order), and the guide: the spatially weighted mean g_i of
  // their luminance with its variance. The range kernel compares neighbours with g_i, not
  // with y_i: against a noisy centre it would favour the neighbours that share y_i's noise
  // (measured: the filtered noise 2x the prediction on a flat floor).
  std::vector<uint64_t> admissible(count, 0);
  std::vector<float> guide(count), guide_variance(count);
  std::vector<glm::vec2> guide_slope(count);  // per unit of offset / h_i, in i's tangent frame
  std::atomic<uint64_t> rays{0};
  for_each_point(count, context, 0.0, 0.8, [&](size_t i, auto& found, auto& near) {
    const float h2 = nearest_points(tree, points, i, found, near);
    const glm::vec3& x = points.positions[i];
    const glm::vec3& n = points.normals[i];
    const Frame frame(n);
    const float inverse_h = h2 > 0.0f ? 1.0f / std::sqrt(h2) : 0.0f;
    std::vector<float> weights;
    std::vector<glm::vec2> offsets;
    std::vector<uint32_t> members;
    uint64_t mask = 0, traced = 0;
    for (size_t k = 0; k < near.size(); ++k) {
      const uint32_t j = near[k].index;
      const float w = j == i ? 1.0f : spatial_weight(near[k], h2);
      const glm::vec3 d = points.positions[j] - x;
      if (j != i) {
        if (!(w > 1e-4f)) continue;
        const glm::vec3& nj = points.normals[j];
        if (!(glm::dot(n, nj) >= kMinNormalCosine)) continue;
        if (std::abs(glm::dot(d, n)) > kMaxPlaneSlope * std::sqrt(near[k].distance_squared)) {
          continue;
        }
        ++traced;
        if (!points_see_each_other(tracer, x, n, points.positions[j], nj, ray_epsilon)) continue;
      }
      mask |= uint64_t(1) << k;
      weights.push_back(w);
      offsets.push_back(inverse_h * glm::vec2(glm::dot(d, frame.tangent),
                                              glm::dot(d, frame.bitangent)));
      members.push_back(j);
    }
    std::vector<double> kernel;
    std::vector<glm::dvec2> slope_kernel;
    local_linear_kernel(weights, offsets, kernel, &slope_kernel);
    double value = 0.0, variance = 0.0;
    glm::dvec2 slope(0.0);
    for (size_t m = 0; m < members.size(); ++m) {
      value += kernel[m] * luminances[members[m]];
      slope += slope_kernel[m] * double(luminances[members[m]]);
      variance += kernel[m] * kernel[m] * double(variance_of_mean[members[m]]);
    }
    // The plane guides the range kernel only where it fits to within the noise: across a
    // step it would pass for a ramp and let the other side in.
    double residual = 0.0, noise = 0.0;
    for (size_t m = 0; m < members.size(); ++m) {
      const double r = luminances[members[m]] - value - glm::dot(slope, glm::dvec2(offsets[m]));
      residual += weights[m] * r * r;
      noise += weights[m] * double(variance_of_mean[members[m]]);
    }
    const bool planar = residual <= kPlaneFitTolerance * noise;
    admissible[i] = mask;
    guide[i] = float(value);
    guide_slope[i] = planar ? glm::vec2(slope) : glm::vec2(0.0f);
    guide_variance[i] = float(variance);
    rays.fetch_add(traced, std::memory_order_relaxed);
  });

  // Pass 2: the admissible neighbours (the point itself included) weighted by distance and
  // by how far their value lies from the guide beyond the noise of both.
  std::vector<glm::vec3> filtered(count);
  std::vector<float> filtered_variance(count);
  for_each_point(count, context, 0.8, 1.0, [&](size_t i, auto& found, auto& near) {
    const float h2 = nearest_points(tree, points, i, found, near);
    const glm::vec3& x = points.positions[i];
    const Frame frame(points.normals[i]);
    const float inverse_h = h2 > 0.0f ? 1.0f / std::sqrt(h2) : 0.0f;
    std::vector<float> weights;
    std::vector<glm::vec2> offsets;
    std::vector<uint32_t> members;
    for (size_t k = 0; k < near.size(); ++k) {
      if (!(admissible[i] >> k & 1)) continue;
      const uint32_t j = near[k].index;
      // The point itself always counts fully: where every neighbour lies far from the guide
      // (at an edge the guide mixes both sides) the point keeps its own value.
      const glm::vec3 d = points.positions[j] - x;
      const glm::vec2 offset =
          inverse_h * glm::vec2(glm::dot(d, frame.tangent), glm::dot(d, frame.bitangent));
      float w = 1.0f;
      if (j != i) {
        const float noise = guide_variance[i] + variance_of_mean[j];
        if (!(noise > 0.0f)) continue;  // noise-free: nothing to trade
        // Against the guide's plane at j: against its value at i a gradient would favour the
        // neighbours whose noise leans towards i (measured: a bias at a ramp's rim).
        const float difference = guide[i] + glm::dot(guide_slope[i], offset) - luminances[j];
        const float excess = std::max(0.0f, difference * difference - noise);
        w = spatial_weight(near[k], h2) *
            std::exp(-excess / (kRangeStrength * kRangeStrength * noise));
      }
      weights.push_back(w);
      offsets.push_back(offset);
      members.push_back(j);
    }
    std::vector<double> kernel;
    local_linear_kernel(weights, offsets, kernel);
    glm::dvec3 value(0.0);
    double variance = 0.0;
    for (size_t m = 0; m < members.size(); ++m) {
      value += kernel[m] * glm::dvec3(values[members[m]]);
      variance += kernel[m] * kernel[m] * double(variance_of_mean[members[m]]);
    }
    // A slope fitted from noise can extrapolate below zero; light cannot.
    filtered[i] = glm::max(glm::vec3(value), glm::vec3(0.0f));
    filtered_variance[i] = float(variance);
  });

  double mean = 0.0, before = 0.0, after = 0.0;
  for (size_t i = 0; i < count; ++i) {
    mean += double(luminances[i]);
    before += double(variance_of_mean[i]);
    after += double(filtered_variance[i]);
  }
  std::copy(filtered.begin(), filtered.end(), values.begin());
  if (mean > 0.0) {
    statistics.noise_before = std::sqrt(before / double(count)) / (mean / double(count));
    statistics.noise_after = std::sqrt(after / double(count)) / (mean / double(count));
  }
  statistics.rays = rays.load();
  return statistics;
}

}  // namespace bakegi
