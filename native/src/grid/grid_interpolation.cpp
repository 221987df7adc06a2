#include "grid/grid_interpolation.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Trilinear: the two vertices around x on one axis and their weights (clamped at the ends).
struct Taps {
  uint32_t index[4];
  float weight[4];
  int count;
};

Taps linear_taps(float x, uint32_t n) {
  x = std::clamp(x, 0.0f, float(n - 1));
  const uint32_t lo = std::min(uint32_t(x), n - 2);
  const float t = x - float(lo);
  return {{lo, lo + 1, 0, 0}, {1.0f - t, t, 0.0f, 0.0f}, 2};
}

// Uniform cubic B-spline over the four vertices around x; indices past the ends repeat the
// end vertex (the grid's values extend as constants beyond its outer vertices).
Taps cubic_taps(float x, uint32_t n) {
  x = std::clamp(x, 0.0f, float(n - 1));
  const float base = std::floor(x);
  const float t = x - base;
  const float s = 1.0f - t;
  Taps taps;
  taps.count = 4;
  taps.weight[0] = s * s * s / 6.0f;
  taps.weight[1] = (4.0f - 6.0f * t * t + 3.0f * t * t * t) / 6.0f;
  taps.weight[2] = (4.0f - 6.0f * s * s + 3.0f * s * s * s) / 6.0f;
  taps.weight[3] = t * t * t / 6.0f;
  for (int o = 0; o < 4; ++o) {
    const int64_t i = int64_t(base) - 1 + o;
    taps.index[o] = uint32_t(std::clamp<int64_t>(i, 0, int64_t(n) - 1));
  }
  return taps;
}

}  // namespace

glm::vec3 evaluate_grid(const IrradianceVectorGrid& grid, const glm::vec3& position,
                        const glm::vec3& normal, GridInterpolation interpolation,
                        GridDirectionalWeights weights, const VertexFilter* filter,
                        bool* all_refused) {
  if (all_refused) *all_refused = false;
  const float length = glm::length(normal);
  if (!(length > 0.0f) || !std::isfinite(length)) return glm::vec3(0.0f);
  const glm::vec3 n = normal / length;
  const GridLayout& layout = grid.layout;
  glm::vec3 g = layout.grid_coordinates(position);
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(g[a])) g[a] = 0.0f;
  }
  Taps taps[3];
  for (int a = 0; a < 3; ++a) {
    taps[a] = interpolation == GridInterpolation::kTricubic
                  ? cubic_taps(g[a], layout.resolution[a])
                  : linear_taps(g[a], layout.resolution[a]);
  }
  // The spatial taps (at most 4^3) and their weights, which sum to 1.
  size_t vertex[64];
  float weight[64];
  int count = 0;
  for (int tk = 0; tk < taps[2].count; ++tk) {
    for (int tj = 0; tj < taps[1].count; ++tj) {
      for (int ti = 0; ti < taps[0].count; ++ti) {
        const float w = taps[0].weight[ti] * taps[1].weight[tj] * taps[2].weight[tk];
        if (w == 0.0f) continue;
        vertex[count] =
            layout.vertex_index(taps[0].index[ti], taps[1].index[tj], taps[2].index[tk]);
        weight[count++] = w;
      }
    }
  }
  if (filter) {
    // Refused vertices drop out and the others share their weight; when every one is
    // refused the point reads them all (and says so).
    float kept[64], kept_total = 0.0f;
    for (int i = 0; i < count; ++i) {
      kept[i] = (*filter)(vertex[i], layout.vertex_position(vertex[i])) ? weight[i] : 0.0f;
      kept_total += kept[i];
    }
    if (kept_total > 1e-6f) {
      for (int i = 0; i < count; ++i) weight[i] = kept[i] / kept_total;
    } else if (all_refused) {
      *all_refused = true;
    }
  }
  return blend_vertices(grid, n, std::span<const size_t>(vertex, count),
                        std::span<const float>(weight, count), weights);
}

glm::vec3 blend_vertices(const IrradianceVectorGrid& grid, const glm::vec3& n,
                         std::span<const size_t> vertices, std::span<const float> spatial,
                         GridDirectionalWeights weights) {
  // I_n = sum over axes of (directional weight) * (spatially interpolated hemisphere on n's
  // side of the axis).
  glm::mat3 blended(0.0f);
  for (size_t i = 0; i < vertices.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      const float directional =
          weights == GridDirectionalWeights::kSquared ? n[a] * n[a] : std::abs(n[a]);
      if (directional == 0.0f) continue;
      const int h = 2 * a + (n[a] >= 0.0f ? 0 : 1);
      blended += (spatial[i] * directional) * grid.at(vertices[i], h);
    }
  }
  return glm::max(
      glm::vec3(glm::dot(blended[0], n), glm::dot(blended[1], n), glm::dot(blended[2], n)) * kInvPi,
      glm::vec3(0.0f));
}

void evaluate_grid(const IrradianceVectorGrid& grid, std::span<const glm::vec3> positions,
                   std::span<const glm::vec3> normals, std::span<glm::vec3> out,
                   GridInterpolation interpolation, GridDirectionalWeights weights) {
  if (positions.size() != normals.size() || out.size() != positions.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL,
                "grid evaluation: sizes of positions, normals and output differ");
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t i = block.begin(); i != block.end(); ++i) {
                        out[i] =
                            evaluate_grid(grid, positions[i], normals[i], interpolation, weights);
                      }
                    });
}

}  // namespace bakegi
