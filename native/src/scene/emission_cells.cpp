#include "scene/emission_cells.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/scene.h"
#include "scene/triangle_cells.h"

namespace bakegi {

namespace {

float channel_sum(const glm::vec3& c) {
  return std::max(0.0f, c.x) + std::max(0.0f, c.y) + std::max(0.0f, c.z);
}

// Texels under the triangle's UVs (repeats counted).
double texel_footprint(const Triangle& t, const Texture& texture) {
  const glm::dvec2 e1 = glm::dvec2(t.uv[1]) - glm::dvec2(t.uv[0]);
  const glm::dvec2 e2 = glm::dvec2(t.uv[2]) - glm::dvec2(t.uv[0]);
  return 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x) * double(texture.width) * double(texture.height);
}

// Quadrature points of a cell: the centroids of its own level-s cells (equal areas, so the
// mean is their plain average; the midpoint rule, exact for linear variation).
std::vector<glm::vec2> cell_quadrature(uint32_t s) {
  std::vector<glm::vec2> points;
  for (uint32_t q = 0; q < triangle_cell_count(s); ++q) {
    const auto c = triangle_cell_corners(s, q);
    points.push_back((c[0] + c[1] + c[2]) / 3.0f);
  }
  return points;
}

}  // namespace

EmissionCells build_emission_cells(const Scene& scene, const EmissionCellLimits& limits) {
  const std::vector<uint32_t>& emitters = scene.emissive_triangles;
  const size_t n = emitters.size();
  auto texture_of = [&](size_t e) -> const Texture* {
    const Material& m = scene.material_of(scene.triangles[emitters[e]]);
    return m.emission_texture == BAKEGI_NO_TEXTURE
               ? nullptr
               : &scene.description.textures[m.emission_texture];
  };

  // Levels: cells of about kTexelsPerCell texels, shrunk evenly to fit the cell limit.
  EmissionCells cells;
  cells.level.assign(n, 1);
  std::vector<double> footprint(n, 0.0);
  double cell_total = 0.0;
  for (size_t e = 0; e < n; ++e) {
    if (const Texture* texture = texture_of(e)) {
      footprint[e] = texel_footprint(scene.triangles[emitters[e]], *texture);
      const double wanted = std::ceil(std::sqrt(footprint[e] / EmissionCells::kTexelsPerCell));
      cells.level[e] = uint32_t(std::clamp(wanted, 1.0, double(EmissionCells::kMaxLevel)));
    }
    cell_total += double(cells.level[e]) * cells.level[e];
  }
  if (cell_total > double(limits.max_cells)) {
    const double shrink = std::sqrt(double(limits.max_cells) / cell_total);
    for (uint32_t& level : cells.level) {
      level = std::max(1u, uint32_t(std::floor(double(level) * shrink)));
    }
  }

  // Quadrature per cell: s² points, about 4 per texel, at least 4 (textured cells only), shrunk
  // evenly to fit the lookup limit.
  std::vector<uint32_t> quadrature(n, 0);
  double lookups = 0.0;
  for (size_t e = 0; e < n; ++e) {
    if (!texture_of(e)) continue;
    const double cell_count = double(cells.level[e]) * cells.level[e];
    const double wanted = std::ceil(2.0 * std::sqrt(footprint[e] / cell_count));
    quadrature[e] = uint32_t(std::clamp(wanted, 2.0, 8.0));
    lookups += cell_count * quadrature[e] * quadrature[e];
  }
  if (lookups > double(limits.max_lookups)) {
    const double shrink = std::sqrt(double(limits.max_lookups) / lookups);
    for (uint32_t& s : quadrature) {
      if (s > 0) s = std::max(1u, uint32_t(std::floor(double(s) * shrink)));
    }
  }

  cells.first.assign(n + 1, 0);
  for (size_t e = 0; e < n; ++e) {
    const uint32_t count = triangle_cell_count(cells.level[e]);
    cells.first[e + 1] = cells.first[e] + count;
    cells.lookups += uint64_t(count) * quadrature[e] * quadrature[e];
  }
  cells.power.assign(cells.first[n], 0.0f);
  std::vector<std::vector<glm::vec2>> points_of_level(9);
  for (uint32_t s = 1; s <= 8; ++s) points_of_level[s] = cell_quadrature(s);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t e = r.begin(); e != r.end(); ++e) {
      const Triangle& t = scene.triangles[emitters[e]];
      if (quadrature[e] == 0) {
        cells.power[cells.first[e]] = channel_sum(scene.material_of(t).emission);
        continue;
      }
      const uint32_t level = cells.level[e];
      const std::vector<glm::vec2>& points = points_of_level[quadrature[e]];
      for (uint32_t c = 0; c < triangle_cell_count(level); ++c) {
        const auto corners = triangle_cell_corners(level, c);
        glm::dvec3 sum(0.0);
        for (const glm::vec2& p : points) {
          const glm::vec2 b = triangle_cell_point(level, corners, p);
          sum += glm::dvec3(scene.emission_at(t, b.x, b.y));
        }
        cells.power[cells.first[e] + c] = channel_sum(glm::vec3(sum / double(points.size())));
      }
    }
  });
  return cells;
}

}  // namespace bakegi
