#include "grid/grid_push_pull.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace bakegi {

namespace {

constexpr int kValues = kGridHemispheres * 9;  // floats per vertex

struct Level {
  std::array<uint32_t, 3> n{};
  std::vector<float> values;  // kValues per vertex
  std::vector<float> weight;  // 0: nothing known there

  size_t index(uint32_t i, uint32_t j, uint32_t k) const {
    return (size_t(k) * n[1] + j) * n[0] + i;
  }
};

// Cell-centred levels: coarse vertex c sits between fine vertices 2c and 2c + 1 (at fine
// coordinate 2c + 0.5); the tent over fine 2c - 1 .. 2c + 2 has weights 1, 3, 3, 1.
constexpr float kTent[4] = {1.0f, 3.0f, 3.0f, 1.0f};

Level push(const Level& fine) {
  Level coarse;
  for (int a = 0; a < 3; ++a) coarse.n[a] = std::max(1u, (fine.n[a] + 1) / 2);
  const size_t count = size_t(coarse.n[0]) * coarse.n[1] * coarse.n[2];
  coarse.values.assign(count * kValues, 0.0f);
  coarse.weight.assign(count, 0.0f);
  for (uint32_t k = 0; k < coarse.n[2]; ++k) {
    for (uint32_t j = 0; j < coarse.n[1]; ++j) {
      for (uint32_t i = 0; i < coarse.n[0]; ++i) {
        const size_t c = coarse.index(i, j, k);
        float total = 0.0f, filter_total = 0.0f;
        float* out = &coarse.values[c * kValues];
        for (int dk = 0; dk < 4; ++dk) {
          const int64_t fk = int64_t(2 * k) - 1 + dk;
          if (fk < 0 || fk >= fine.n[2]) continue;
          for (int dj = 0; dj < 4; ++dj) {
            const int64_t fj = int64_t(2 * j) - 1 + dj;
            if (fj < 0 || fj >= fine.n[1]) continue;
            for (int di = 0; di < 4; ++di) {
              const int64_t fi = int64_t(2 * i) - 1 + di;
              if (fi < 0 || fi >= fine.n[0]) continue;
              const float filter = kTent[di] * kTent[dj] * kTent[dk];
              const size_t f = fine.index(uint32_t(fi), uint32_t(fj), uint32_t(fk));
              filter_total += filter;
              const float w = filter * fine.weight[f];
              if (w == 0.0f) continue;
              total += w;
              const float* in = &fine.values[f * kValues];
              for (int v = 0; v < kValues; ++v) out[v] += w * in[v];
            }
          }
        }
        if (total > 0.0f) {
          for (int v = 0; v < kValues; ++v) out[v] /= total;
          // How much of the footprint was known: partly known coarse vertices count less
          // when the next level averages them (Gortler et al.'s push-pull weights).
          coarse.weight[c] = std::min(1.0f, total / filter_total * 8.0f);
        }
      }
    }
  }
  return coarse;
}

// Fills the fine level's unknown vertices from the (complete) coarse level, trilinearly.
void pull(Level& fine, const Level& coarse) {
  for (uint32_t k = 0; k < fine.n[2]; ++k) {
    for (uint32_t j = 0; j < fine.n[1]; ++j) {
      for (uint32_t i = 0; i < fine.n[0]; ++i) {
        const size_t f = fine.index(i, j, k);
        if (fine.weight[f] >= 1.0f) continue;
        // Fine vertex x sits at coarse coordinate (x - 0.5) / 2.
        const uint32_t fc[3] = {i, j, k};
        uint32_t lo[3], hi[3];
        float t[3];
        for (int a = 0; a < 3; ++a) {
          const float x = std::clamp((float(fc[a]) - 0.5f) * 0.5f, 0.0f, float(coarse.n[a] - 1));
          lo[a] = uint32_t(std::floor(x));
          hi[a] = std::min(lo[a] + 1, coarse.n[a] - 1);
          t[a] = x - float(lo[a]);
        }
        float blended[kValues] = {};
        for (int corner = 0; corner < 8; ++corner) {
          const uint32_t ci = (corner & 1) ? hi[0] : lo[0];
          const uint32_t cj = (corner & 2) ? hi[1] : lo[1];
          const uint32_t ck = (corner & 4) ? hi[2] : lo[2];
          const float w = ((corner & 1) ? t[0] : 1.0f - t[0]) *
                          ((corner & 2) ? t[1] : 1.0f - t[1]) * ((corner & 4) ? t[2] : 1.0f - t[2]);
          if (w == 0.0f) continue;
          const float* in = &coarse.values[coarse.index(ci, cj, ck) * kValues];
          for (int v = 0; v < kValues; ++v) blended[v] += w * in[v];
        }
        // A partly known vertex (an inner level's) keeps its own part, the rest is pulled.
        const float own = fine.weight[f];
        float* out = &fine.values[f * kValues];
        for (int v = 0; v < kValues; ++v) out[v] = own * out[v] + (1.0f - own) * blended[v];
        fine.weight[f] = 1.0f;
      }
    }
  }
}

// One component of the grid's vertices as the finest level: known where valid.
Level finest_level(const IrradianceVectorGrid& grid, const std::vector<glm::mat3>& vectors) {
  const size_t count = grid.vertex_count();
  Level finest;
  finest.n = grid.layout.resolution;
  finest.values.resize(count * kValues);
  finest.weight.resize(count);
  for (size_t v = 0; v < count; ++v) {
    finest.weight[v] = grid.valid[v] ? 1.0f : 0.0f;
    for (int h = 0; h < kGridHemispheres; ++h) {
      const glm::mat3& m = vectors[v * kGridHemispheres + h];
      for (int c = 0; c < 3; ++c) {
        for (int e = 0; e < 3; ++e) finest.values[v * kValues + h * 9 + c * 3 + e] = m[c][e];
      }
    }
  }
  return finest;
}

// Fills the invalid vertices of one component (the vectors, or the emitted light).
void fill_component(const IrradianceVectorGrid& grid, std::vector<glm::mat3>& vectors) {
  std::vector<Level> levels;
  levels.push_back(finest_level(grid, vectors));
  while (levels.back().n[0] > 1 || levels.back().n[1] > 1 || levels.back().n[2] > 1) {
    levels.push_back(push(levels.back()));
  }
  // The coarsest level is one vertex holding the weighted mean of everything known.
  levels.back().weight.assign(levels.back().weight.size(), 1.0f);
  for (size_t l = levels.size() - 1; l-- > 0;) pull(levels[l], levels[l + 1]);
  const Level& finest = levels[0];

  for (size_t v = 0; v < grid.vertex_count(); ++v) {
    if (grid.valid[v]) continue;
    for (int h = 0; h < kGridHemispheres; ++h) {
      glm::mat3& m = vectors[v * kGridHemispheres + h];
      for (int c = 0; c < 3; ++c) {
        for (int e = 0; e < 3; ++e) m[c][e] = finest.values[v * kValues + h * 9 + c * 3 + e];
      }
    }
  }
}

}  // namespace

size_t fill_invalid_vertices(IrradianceVectorGrid& grid) {
  const size_t count = grid.vertex_count();
  const size_t invalid = size_t(std::count(grid.valid.begin(), grid.valid.end(), uint8_t(0)));
  if (invalid == 0 || invalid == count) return 0;
  fill_component(grid, grid.vectors);
  if (grid.has_emitted()) fill_component(grid, grid.emitted);
  return invalid;
}

}  // namespace bakegi
