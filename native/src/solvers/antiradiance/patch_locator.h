// Which patch of the element hierarchy holds a point of a triangle: the patch a ray hit lands
// on, found from the hit's barycentrics.
//
// A triangle split k times 4-way (element_hierarchy.h) is a regular lattice of 4^k patches in
// its barycentric coordinates (u, v) = (b1, b2) with N = 2^k cells per side: cell (i, j) =
// (⌊N u⌋, ⌊N v⌋) holds an upright patch where the fractional parts sum below 1 and an inverted
// one above. A sliver bisected into pieces (triangle_bisection.h, at half the patch size): the hit's
// piece is found by descending the same cuts from its barycentrics, keyed by its code to the patch that holds it (its group's or
// its own). The triangles of a
// merged patch are level 0: each maps to that patch whole.
#pragma once

#include <cstdint>
#include <unordered_map>

#include "solvers/antiradiance/element_hierarchy.h"

namespace bakegi {
struct Scene;
}

namespace bakegi::antiradiance {

class PatchLocator {
 public:
  static constexpr uint32_t kNone = 0xffffffffu;

  PatchLocator() = default;
  // `scene` must outlive the locator.
  PatchLocator(const Scene& scene, const ElementHierarchy& hierarchy);

  // The patch (index into hierarchy.patches()) at barycentrics (b1, b2) of `triangle`, on its
  // back side when `back` (kNone where that side has no patch: the inside of a solid).
  uint32_t find(uint32_t triangle, float b1, float b2, bool back) const;
  size_t memory_bytes() const;

 private:
  static uint64_t key(uint32_t triangle, bool back, uint32_t code);

  static constexpr uint16_t kSliver = 0xffff;

  const Scene* scene_ = nullptr;
  float piece_size_ = 0.0f;  // slivers are cut into pieces of half the patch size
  std::unordered_map<uint64_t, uint32_t> patches_;
  std::unordered_map<uint32_t, uint16_t> schemes_;  // per triangle: 4-way level or kSliver
};

}  // namespace bakegi::antiradiance
