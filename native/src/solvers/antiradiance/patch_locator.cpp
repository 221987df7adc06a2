#include "solvers/antiradiance/patch_locator.h"

#include <algorithm>
#include <cmath>

#include "scene/scene.h"
#include "scene/triangle_geometry.h"
#include "solvers/antiradiance/triangle_bisection.h"

namespace bakegi::antiradiance {

namespace {

// The 4-way lattice cell of (u, v) at `level`: 15 + 15 bits of cell and 1 of orientation.
uint32_t lattice_code(float b1, float b2, int level) {
  const float n = float(1u << level);
  const float u = std::clamp(b1, 0.0f, 1.0f) * n, v = std::clamp(b2, 0.0f, 1.0f) * n;
  const uint32_t i = uint32_t(std::clamp(std::floor(u), 0.0f, n - 1.0f));
  const uint32_t j = uint32_t(std::clamp(std::floor(v), 0.0f, n - 1.0f));
  const bool inverted = (u - float(i)) + (v - float(j)) > 1.0f;
  return (uint32_t(inverted) << 30) | ((i & 0x7fffu) << 15) | (j & 0x7fffu);
}

}  // namespace

uint64_t PatchLocator::key(uint32_t triangle, bool back, uint32_t code) {
  // 32 bits of triangle, 1 side, 31 of code (a lattice cell or a sliver piece).
  return (uint64_t(triangle) << 32) | (uint64_t(back) << 31) | uint64_t(code & 0x7fffffffu);
}

PatchLocator::PatchLocator(const Scene& scene, const ElementHierarchy& hierarchy)
    : scene_(&scene), piece_size_(0.5f * hierarchy.max_edge()) {
  const auto& patches = hierarchy.patches();
  patches_.reserve(patches.size() + hierarchy.member_count());
  for (size_t p = 0; p < patches.size(); ++p) {
    const Patch& patch = patches[p];
    if (patch.member_count > 0) {
      // A merged patch is whole triangles: every point of each belongs to it.
      for (const MemberTriangle& member : hierarchy.members(patch)) {
        patches_[key(member.triangle, patch.back_side, member.code)] = uint32_t(p);
        schemes_[member.triangle] = member.code != 0 ? kSliver : 0;
      }
      continue;
    }
    if (patch.sliver_piece != 0) {
      patches_[key(patch.triangle, patch.back_side, patch.sliver_piece)] = uint32_t(p);
      schemes_[patch.triangle] = kSliver;
      continue;
    }
    // 4-way: keyed by the lattice cell of the patch's own centroid, so the lookup does not
    // depend on the order in which the hierarchy stores a triangle's patches.
    const Triangle& t = scene.triangles[patch.triangle];
    const glm::vec3 centroid = (patch.corners[0] + patch.corners[1] + patch.corners[2]) / 3.0f;
    const glm::vec2 uv = barycentrics_of(t.p, centroid);
    patches_[key(patch.triangle, patch.back_side,
                 lattice_code(uv.x, uv.y, patch.subdivision_level))] = uint32_t(p);
    schemes_[patch.triangle] = patch.subdivision_level;
  }
}

uint32_t PatchLocator::find(uint32_t triangle, float b1, float b2, bool back) const {
  const auto scheme = schemes_.find(triangle);
  if (scene_ == nullptr || scheme == schemes_.end()) return kNone;
  if (scheme->second == kSliver) {
    const uint32_t code = bisection_piece_at(scene_->triangles[triangle], piece_size_, b1, b2);
    const auto found = patches_.find(key(triangle, back, code));
    return found == patches_.end() ? kNone : found->second;
  }
  const int level = scheme->second;
  auto found = patches_.find(key(triangle, back, lattice_code(b1, b2, level)));
  if (found == patches_.end()) {  // on the lattice's outer edge: the upright one
    found = patches_.find(key(triangle, back, lattice_code(b1, b2, level) & ~(1u << 30)));
  }
  return found == patches_.end() ? kNone : found->second;
}

size_t PatchLocator::memory_bytes() const {
  return patches_.size() * (sizeof(uint64_t) + sizeof(uint32_t) + 2 * sizeof(void*)) +
         schemes_.size() * (sizeof(uint32_t) + sizeof(uint16_t) + 2 * sizeof(void*));
}

}  // namespace bakegi::antiradiance
