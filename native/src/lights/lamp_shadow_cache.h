// Where each lamp cannot light, learned before a bake, so that its shadow rays there are
// mostly skipped. A pilot traces one shadow ray to every lamp from points spread over the
// surfaces by area (either side of each surface: the side that faces the lamp), counted per
// cell of a grid over the scene. Where every pilot ray of a cell found a lamp blocked (the far
// side of a wall, a room the sun does not reach), a light sample of that lamp is kept only
// with probability kKeptWhereBlocked and then weighed by its inverse: still unbiased (a lit
// spot the pilot missed only costs noise), with most of the rays that could only find a wall
// left untraced. Deterministic: the pilot's points and numbers follow from the scene alone,
// and DirectLight decides on a hash of the sample's own numbers, so that a bake changes only
// where samples are skipped (docs/benchmarks.md 0m).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

class DirectLight;
struct Scene;

class LampShadowCache {
 public:
  // Probability with which a light sample is kept where the pilot found the lamp blocked.
  static constexpr float kKeptWhereBlocked = 0.125f;
  // A cell is judged by at least this many pilot rays, or every sample there is kept.
  static constexpr uint32_t kMinimumTests = 8;

  // Lamps past this many (in DirectLight's order) are always traced: the pilot's rays and
  // the cache's memory grow with the lamps it judges.
  static constexpr size_t kMaxJudgedLamps = 16;

  // The pilot: `points` surface points (0: 2^16, or 2^18 / lamps with more than 4 lamps, at
  // least 2^14: 0.01-0.02 s on the suite), one shadow ray from each to each judged lamp of
  // `direct` that casts shadows, on a grid of `cells_per_side` cells along the scene's
  // longest side (times 6 normal directions). Counts its shadow rays into `rays`.
  static LampShadowCache build(const Scene& scene, const DirectLight& direct, uint64_t& rays,
                               size_t points = 0, int cells_per_side = 16);

  // The probability with which a sample of lamp `lamp` (DirectLight's order) at `position`
  // is kept: 1, or kKeptWhereBlocked where the lamp is blocked throughout the cell.
  float kept_probability(size_t lamp, const glm::vec3& position, const glm::vec3& normal) const {
    if (lamp >= blocked_.size() || blocked_[lamp].empty()) return 1.0f;
    const int64_t cell = cell_of(position, normal);
    return cell >= 0 && blocked_[lamp][size_t(cell)] ? kKeptWhereBlocked : 1.0f;
  }

  // Of the cells the pilot judged, the share where each lamp is blocked (tests, studies).
  std::vector<float> blocked_shares() const;

 private:
  // The cell of a point and the axis direction nearest its normal (6 per grid cell): surfaces
  // of other orientations in one grid cell (a table's top and its legs) are judged apart.
  int64_t cell_of(const glm::vec3& p, const glm::vec3& normal) const {
    const int64_t c = grid_cell_of(p);
    if (c < 0) return -1;
    const glm::vec3 a = glm::abs(normal);
    const int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    return c * 6 + axis * 2 + (normal[axis] < 0.0f ? 1 : 0);
  }
  int64_t grid_cell_of(const glm::vec3& p) const {
    const glm::vec3 f = (p - origin_) * inverse_cell_;
    if (!(f.x >= 0.0f && f.y >= 0.0f && f.z >= 0.0f)) return -1;
    const int64_t x = std::min(int64_t(f.x), int64_t(resolution_.x - 1));
    const int64_t y = std::min(int64_t(f.y), int64_t(resolution_.y - 1));
    const int64_t z = std::min(int64_t(f.z), int64_t(resolution_.z - 1));
    return (z * resolution_.y + y) * resolution_.x + x;
  }

  glm::vec3 origin_{0.0f};
  float inverse_cell_ = 0.0f;
  glm::ivec3 resolution_{1};
  std::vector<std::vector<uint8_t>> blocked_;  // per lamp, per cell: 1 = blocked throughout
  std::vector<uint32_t> judged_;               // per lamp: cells with enough pilot rays
};

}  // namespace bakegi
