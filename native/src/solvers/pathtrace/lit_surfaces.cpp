#include "solvers/pathtrace/lit_surfaces.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "scene/triangle_cells.h"
#include "util/job_context.h"
#include "util/luminance.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Subdivision level of every triangle: cells of about total area / target_cells each.
std::vector<uint8_t> cell_levels(const Scene& scene, uint64_t target_cells) {
  double total_area = 0.0;
  for (const Triangle& t : scene.triangles) total_area += double(t.area);
  const double cell_area = total_area / double(std::max<uint64_t>(target_cells, 1));
  std::vector<uint8_t> levels(scene.triangles.size(), 1);
  if (!(cell_area > 0.0)) return levels;
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    const double per_side = std::ceil(std::sqrt(double(scene.triangles[i].area) / cell_area));
    levels[i] = uint8_t(std::clamp(per_side, 1.0, double(LitSurfaces::kMaxLevel)));
  }
  return levels;
}

// The surface of triangle t at barycentrics b, seen from the side of `side_normal`.
SurfacePoint surface_on_side(const Triangle& t, glm::vec2 b, const glm::vec3& side_normal) {
  const float b0 = 1.0f - b.x - b.y;
  SurfacePoint x;
  x.position = t.p[0] * b0 + t.p[1] * b.x + t.p[2] * b.y;
  x.geometric_normal = side_normal;
  const glm::vec3 interpolated = t.n[0] * b0 + t.n[1] * b.x + t.n[2] * b.y;
  const float length = glm::length(interpolated);
  glm::vec3 shading = length > 1e-12f ? interpolated / length : side_normal;
  if (glm::dot(shading, side_normal) < 0.0f) shading = -shading;
  x.shading_normal = shading;
  return x;
}

}  // namespace

uint64_t LitSurfaces::cell_count(const DirectLight& direct, uint64_t target_cells) {
  uint64_t count = 0;
  for (uint8_t level : cell_levels(direct.scene(), target_cells)) {
    count += triangle_cell_count(level);
  }
  return count;
}

LitSurfaces::LitSurfaces(const DirectLight& direct, uint64_t target_cells, uint64_t seed,
                         JobContext& context)
    : direct_(direct) {
  const Scene& scene = direct.scene();
  const size_t n = scene.triangles.size();
  level_ = cell_levels(scene, target_cells);
  first_cell_.assign(n + 1, 0);
  for (size_t i = 0; i < n; ++i) first_cell_[i + 1] = first_cell_[i] + level_[i] * level_[i];
  const uint64_t cell_total = first_cell_[n];
  // Power per cell first (in cdf_), then the running sum.
  cdf_.assign(cell_total, 0.0);
  pdf_over_area_.assign(cell_total, 0.0f);
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& range) {
        context.throw_if_cancelled();
        uint64_t block_rays = 0;
        for (size_t i = range.begin(); i != range.end(); ++i) {
          const Triangle& t = scene.triangles[i];
          const uint32_t level = level_[i];
          const double cell_area = double(t.area) / double(triangle_cell_count(level));
          for (uint32_t c = 0; c < triangle_cell_count(level); ++c) {
            RandomStream rng = sample_stream(seed, first_cell_[i] + c, 0);
            const glm::vec2 b = triangle_cell_point(
                level, triangle_cell_corners(level, c),
                sample_triangle_barycentrics(rng.next_float(), rng.next_float()));
            const double albedo = luminance(scene.albedo_at(t, b.x, b.y));
            if (!(albedo > 0.0) || !(cell_area > 0.0)) continue;
            // Both sides: the gathers that reach this cell come from either.
            double irradiance = 0.0;
            for (const float side : {1.0f, -1.0f}) {
              const SurfacePoint x = surface_on_side(t, b, side * t.face_normal);
              irradiance += luminance(direct.sample_lights(x, rng, block_rays));
            }
            if (irradiance > 0.0 && std::isfinite(irradiance)) {
              cdf_[first_cell_[i] + c] = albedo * irradiance * cell_area;
            }
          }
        }
        rays.fetch_add(block_rays, std::memory_order_relaxed);
      });
  context.throw_if_cancelled();
  rays_ = rays.load();

  double area = 0.0, power_squared_over_area = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double cell_area = double(scene.triangles[i].area) / double(level_[i] * level_[i]);
    for (uint64_t c = first_cell_[i]; c < first_cell_[i + 1]; ++c) {
      const double power = cdf_[c];
      area += cell_area;
      total_power_ += power;
      if (power > 0.0) power_squared_over_area += power * power / cell_area;
    }
  }
  if (!(total_power_ > 0.0)) {
    cdf_.clear();
    pdf_over_area_.clear();
    return;
  }
  spread_ = total_power_ * total_power_ / (area * power_squared_over_area);
  double running = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double cell_area = double(scene.triangles[i].area) / double(level_[i] * level_[i]);
    for (uint64_t c = first_cell_[i]; c < first_cell_[i + 1]; ++c) {
      const double probability = cdf_[c] / total_power_;
      pdf_over_area_[c] = float(probability / cell_area);
      running += probability;
      cdf_[c] = running;
    }
  }
  cdf_.back() = 1.0;
}

bool LitSurfaces::sample(float u_pick, float u1, float u2, LitSurfacePoint& out) const {
  if (empty()) return false;
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u_pick));
  const uint64_t cell = std::min<uint64_t>(uint64_t(it - cdf_.begin()), cdf_.size() - 1);
  if (!(pdf_over_area_[cell] > 0.0f)) return false;
  const uint32_t triangle =
      uint32_t(std::upper_bound(first_cell_.begin(), first_cell_.end(), cell) -
               first_cell_.begin()) - 1;
  const uint32_t level = level_[triangle];
  const glm::vec2 b =
      triangle_cell_point(level, triangle_cell_corners(level, uint32_t(cell - first_cell_[triangle])),
                          sample_triangle_barycentrics(u1, u2));
  const Triangle& t = direct_.scene().triangles[triangle];
  out.position = t.p[0] * (1.0f - b.x - b.y) + t.p[1] * b.x + t.p[2] * b.y;
  out.triangle = triangle;
  out.b1 = b.x;
  out.b2 = b.y;
  out.pdf_area = pdf_over_area_[cell];
  return true;
}

float LitSurfaces::pdf_area(uint32_t triangle, float b1, float b2) const {
  if (empty()) return 0.0f;
  return pdf_over_area_[first_cell_[triangle] +
                        triangle_cell_containing(level_[triangle], b1, b2)];
}

}  // namespace bakegi
