#include "lightmap/texel_sharing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/glm.hpp>

#include "bake/point_sharing.h"

namespace bakegi {

namespace {

// Neighbouring texels count as the same surface for the footprint at normals this close
// (25 degrees): the footprint only sizes the test, the normals are compared again below.
constexpr float kFootprintNormalCosine = 0.9f;

}  // namespace

std::vector<uint32_t> texel_share_candidates(const TexelSamples& samples, uint64_t first_index) {
  const size_t n = samples.size();
  const std::vector<glm::vec3>& position = samples.points.positions;
  const std::vector<glm::vec3>& normal = samples.points.normals;
  std::vector<uint32_t> candidate(n);
  std::iota(candidate.begin(), candidate.end(), 0u);
  // The samples of each texel together, each texel's in sample order.
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return samples.texel[a] < samples.texel[b]; });
  std::vector<uint32_t> texels, first_sample;  // sorted texels and their first samples
  for (size_t k = 0; k < n; ++k) {
    if (k == 0 || samples.texel[order[k]] != samples.texel[order[k - 1]]) {
      texels.push_back(samples.texel[order[k]]);
      first_sample.push_back(order[k]);
    }
  }
  const auto first_in = [&](int64_t x, int64_t y) -> int64_t {
    if (x < 0 || y < 0 || x >= int64_t(samples.width) || y >= int64_t(samples.height)) return -1;
    const uint32_t texel = uint32_t(y * int64_t(samples.width) + x);
    const auto it = std::lower_bound(texels.begin(), texels.end(), texel);
    return it != texels.end() && *it == texel ? int64_t(first_sample[size_t(it - texels.begin())])
                                              : -1;
  };

  std::vector<uint32_t> heads;
  for (size_t begin = 0; begin < n;) {
    const uint32_t texel = samples.texel[order[begin]];
    size_t end = begin;
    while (end < n && samples.texel[order[end]] == texel) ++end;
    if (end - begin > 1) {
      // The texel's footprint: the distance from its first sample to the nearest first
      // sample of a neighbouring texel on the same surface.
      const uint32_t head = order[begin];
      const int64_t x = texel % samples.width, y = texel / samples.width;
      float footprint = std::numeric_limits<float>::infinity();
      const int64_t neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
      for (const auto& [nx, ny] : neighbours) {
        const int64_t j = first_in(nx, ny);
        if (j < 0 || glm::dot(normal[head], normal[size_t(j)]) < kFootprintNormalCosine) continue;
        footprint = std::min(footprint, glm::length(position[size_t(j)] - position[head]));
      }
      if (std::isfinite(footprint) && footprint > 0.0f) {
        const float reach = kTexelShareFootprints * footprint;
        heads.assign(1, head);
        for (size_t k = begin + 1; k < end; ++k) {
          const uint32_t i = order[k];
          for (const uint32_t h : heads) {
            if (glm::dot(normal[i], normal[h]) >= kSharedNormalCosine &&
                glm::length(position[i] - position[h]) <= reach) {
              candidate[i] = h;
              break;
            }
          }
          if (candidate[i] == i) heads.push_back(i);
        }
      }
    }
    begin = end;
  }
  for (uint32_t& c : candidate) c = uint32_t(c + first_index);
  return candidate;
}

}  // namespace bakegi
