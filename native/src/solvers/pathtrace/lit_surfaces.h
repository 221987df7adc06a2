// The directly lit surfaces as lights for the first bounce of a gather (issue 15).
//
// Most of the indirect light at a bake point is direct light reflected once. Where a small
// patch carries it (a spot light's pool on Sponza's floor, a sun patch through a window),
// cosine-weighted rays find the patch rarely and the path tracer's noise is that rarity.
// Here every triangle is cut into cells (scene/triangle_cells.h, about equal area over the
// scene) and each cell gets the power it reflects of the lamps' light, estimated once with
// one light sample per side. A gather can then also pick a cell by that power, a uniform
// point y in it, and connect: one shadow ray, the lamps' light at y (next-event estimation),
// weighed by multiple importance sampling against the cosine-weighted ray that would have
// found the same y (indirect_path.h, sample_indirect_lit).
//
// The cell powers only steer sampling: the light at y is estimated afresh each time, so a
// wrong or noisy power changes noise, not the result, and a cell estimated dark (never
// picked) is still reached by the cosine rays.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

class DirectLight;
class JobContext;

struct LitSurfacePoint {
  glm::vec3 position;
  uint32_t triangle;
  float b1, b2;    // barycentrics of corners 1 and 2
  float pdf_area;  // density of this choice per unit area
};

class LitSurfaces {
 public:
  // Bytes a cell takes (the sampling table and its density).
  static constexpr uint64_t kBytesPerCell = 12;

  // Cuts the scene's triangles into about `target_cells` cells (at least one a triangle,
  // kMaxLevel² at most) and estimates their reflected power with streams from `seed`.
  // Parallel; checks cancel (throws Error(CANCELLED)). Cells whose estimate is 0 are never
  // picked; if all are, empty() is true.
  LitSurfaces(const DirectLight& direct, uint64_t target_cells, uint64_t seed,
              JobContext& context);

  // The cell count the constructor would make for `target_cells`, for memory checks.
  static uint64_t cell_count(const DirectLight& direct, uint64_t target_cells);

  bool empty() const { return cdf_.empty() || !(total_power_ > 0.0); }
  uint64_t cells() const { return pdf_over_area_.size(); }
  uint64_t rays() const { return rays_; }
  // How evenly the reflected power spreads over the area: (Σ P)² / (Σ A · Σ P²/A), 1 when
  // every cell reflects the same power per unit area, the lit fraction of the area when a
  // part is lit evenly and the rest dark.
  double spread() const { return spread_; }

  // Picks a cell by power and a uniform point in it; false if nothing is lit.
  bool sample(float u_pick, float u1, float u2, LitSurfacePoint& out) const;
  // The density per unit area with which sample() returns the point of triangle `triangle`
  // at barycentrics (b1, b2); 0 on cells never picked.
  float pdf_area(uint32_t triangle, float b1, float b2) const;

  static constexpr uint32_t kMaxLevel = 64;

 private:
  const DirectLight& direct_;
  std::vector<uint32_t> first_cell_;  // per triangle, and the total at the end
  std::vector<uint8_t> level_;        // per triangle
  std::vector<double> cdf_;           // over all cells, normalized, back() == 1
  std::vector<float> pdf_over_area_;  // per cell: its probability / its area
  double total_power_ = 0.0;
  double spread_ = 0.0;
  uint64_t rays_ = 0;
};

}  // namespace bakegi
