#include "bake/error_probes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "scene/scene_validation.h"
#include "util/error.h"
#include "util/random.h"
#include "util/luminance.h"

namespace bakegi {

void ErrorProbes::add(const glm::vec3& position, const glm::vec3& normal, uint32_t object_id,
                      const std::array<uint32_t, 4>& indices, const std::array<float, 4>& weights,
                      float sampling_weight) {
  sampling_weights.push_back(sampling_weight);
  points.positions.push_back(position);
  points.normals.push_back(normal);
  points.object_ids.push_back(object_id);
  stencil_points.push_back(indices);
  stencil_weights.push_back(weights);
}

glm::vec3 ErrorProbes::baked_value(size_t i, const std::vector<glm::vec3>& baked) const {
  glm::vec3 value(0.0f);
  for (int j = 0; j < 4; ++j) {
    const float w = stencil_weights[i][size_t(j)];
    if (w > 0.0f) value += w * baked[stencil_points[i][size_t(j)]];
  }
  return value;
}

ErrorProbes probes_at_bake_points(const BakePoints& points, size_t count, uint64_t seed) {
  // A partial Fisher-Yates shuffle of the indices: `count` distinct points, uniformly.
  std::vector<uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  count = std::min(count, order.size());
  Pcg32 rng(mix64(seed ^ 0x5EEDu), 0x9B05688C2B3E6C1Full);
  for (size_t i = 0; i < count; ++i) {
    const uint64_t span = order.size() - i;
    // 64-bit draw from two 32-bit ones, reduced without a visible bias for spans < 2^32.
    const uint64_t draw = (uint64_t(rng.next_uint()) << 32) | rng.next_uint();
    std::swap(order[i], order[i + size_t(draw % span)]);
  }
  order.resize(count);
  std::sort(order.begin(), order.end());  // memory order: the points' own locality
  ErrorProbes probes;
  for (const uint32_t i : order) {
    probes.add(points.positions[i], points.normals[i], points.object_ids[i], {i, 0, 0, 0},
               {1.0f, 0.0f, 0.0f, 0.0f});
  }
  return probes;
}

ErrorProbes probes_weighted_by_light(const BakePoints& points, const std::vector<glm::vec3>& baked,
                                     size_t count, uint64_t seed) {
  const size_t n = points.size();
  if (count >= n || baked.size() != n) return probes_at_bake_points(points, count, seed);
  // Cumulative q_i = 0.5 / n + 0.5 Y_i / Σ Y (Y clamped at 0; non-finite values count 0).
  auto light_at = [&](size_t i) {
    const glm::vec3& c = baked[i];
    const double y = luminance(c);
    return std::isfinite(y) && y > 0.0 ? y : 0.0;
  };
  double light = 0.0;
  for (size_t i = 0; i < n; ++i) light += light_at(i);
  if (!(light > 0.0) || !std::isfinite(light)) return probes_at_bake_points(points, count, seed);
  const double uniform_share = 0.5 / double(n), light_share = 0.5 / light;
  auto probability = [&](size_t i) { return uniform_share + light_share * light_at(i); };
  std::vector<double> cumulative(n);
  double running = 0.0;
  for (size_t i = 0; i < n; ++i) cumulative[i] = running += probability(i);
  Pcg32 rng(mix64(seed ^ 0x119475u), 0x9B05688C2B3E6C1Full);
  std::vector<uint32_t> drawn(count);
  for (uint32_t& index : drawn) {
    const double u = (double(rng.next_uint()) + double(rng.next_uint()) / 4294967296.0) /
                     4294967296.0 * running;
    const size_t at = size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) -
                             cumulative.begin());
    index = uint32_t(std::min(at, n - 1));
  }
  std::sort(drawn.begin(), drawn.end());  // memory order: the points' own locality
  ErrorProbes probes;
  for (const uint32_t i : drawn) {
    probes.add(points.positions[i], points.normals[i], points.object_ids[i], {i, 0, 0, 0},
               {1.0f, 0.0f, 0.0f, 0.0f}, float(1.0 / (double(n) * probability(i))));
  }
  return probes;
}

void check_error_probes(ErrorProbes& probes, size_t bake_point_count) {
  const size_t count = probes.points.positions.size();
  if (probes.points.normals.size() != count || probes.points.object_ids.size() != count ||
      probes.stencil_points.size() != count || probes.stencil_weights.size() != count ||
      (!probes.sampling_weights.empty() && probes.sampling_weights.size() != count)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "display probes: array sizes differ");
  }
  for (size_t i = 0; i < count; ++i) {
    const std::string name = "display probe " + std::to_string(i);
    const glm::vec3& p = probes.points.positions[i];
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) ||
        !position_in_range(p)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  name + ": position is not finite or is out of range (+-1e12 m)");
    }
    const glm::vec3& n = probes.points.normals[i];
    const float length = glm::length(n);
    if (!(std::isfinite(length) && length > 1e-20f)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": normal is zero or not finite");
    }
    probes.points.normals[i] = n / length;
    float sum = 0.0f;
    for (int j = 0; j < 4; ++j) {
      const float w = probes.stencil_weights[i][size_t(j)];
      if (!(std::isfinite(w) && w >= 0.0f)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    name + ": weight " + std::to_string(j) + " is negative or not finite");
      }
      if (w > 0.0f && probes.stencil_points[i][size_t(j)] >= bake_point_count) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    name + ": bake point " + std::to_string(probes.stencil_points[i][size_t(j)]) +
                        " is out of range (" + std::to_string(bake_point_count) +
                        " bake points)");
      }
      sum += w;
    }
    if (!(sum > 0.0f)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": its weights sum to 0");
    }
  }
}

}  // namespace bakegi
