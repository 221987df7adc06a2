#include "solvers/antiradiance/patch_locator.h"

#include <algorithm>
#include <cmath>

#include "scene/scene.h"

namespace bakegi::antiradiance {

namespace {

// Barycentrics (b1, b2) of p in triangle t, by least squares in the triangle's plane.
glm::vec2 barycentrics(const Triangle& t, const glm::vec3& p) {
  const glm::vec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = p - t.p[0];
  const float a = glm::dot(e1, e1), b = glm::dot(e1, e2), c = glm::dot(e2, e2);
  const float r1 = glm::dot(d, e1), r2 = glm::dot(d, e2);
  const float det = a * c - b * b;
  if (!(std::abs(det) > 0.0f)) return glm::vec2(1.0f / 3.0f);
  return glm::vec2((c * r1 - b * r2) / det, (a * r2 - b * r1) / det);
}

}  // namespace

uint64_t PatchLocator::key(uint32_t triangle, bool back, uint32_t i, uint32_t j, bool inverted) {
  // 32 bits of triangle, 1 side, 1 orientation, 15 + 15 bits of cell (levels up to 15).
  return (uint64_t(triangle) << 32) | (uint64_t(back) << 31) | (uint64_t(inverted) << 30) |
         (uint64_t(i & 0x7fffu) << 15) | uint64_t(j & 0x7fffu);
}

PatchLocator::PatchLocator(const Scene& scene, const ElementHierarchy& hierarchy) {
  const auto& patches = hierarchy.patches();
  patches_.reserve(patches.size());
  for (size_t p = 0; p < patches.size(); ++p) {
    const Patch& patch = patches[p];
    if (patch.member_count > 0) {
      // A merged patch is whole triangles: every point of each belongs to it.
      for (const MemberTriangle& member : hierarchy.members(patch)) {
        patches_[key(member.triangle, patch.back_side, 0, 0, false)] = uint32_t(p);
        levels_[member.triangle] = 0;
      }
      continue;
    }
    const Triangle& t = scene.triangles[patch.triangle];
    const glm::vec3 centroid = (patch.corners[0] + patch.corners[1] + patch.corners[2]) / 3.0f;
    const glm::vec2 uv = barycentrics(t, centroid);
    const float n = float(1u << patch.subdivision_level);
    const uint32_t i = uint32_t(std::clamp(std::floor(uv.x * n), 0.0f, n - 1.0f));
    const uint32_t j = uint32_t(std::clamp(std::floor(uv.y * n), 0.0f, n - 1.0f));
    const bool inverted = (uv.x * n - float(i)) + (uv.y * n - float(j)) > 1.0f;
    patches_[key(patch.triangle, patch.back_side, i, j, inverted)] = uint32_t(p);
    levels_[patch.triangle] = patch.subdivision_level;
  }
}

uint32_t PatchLocator::find(uint32_t triangle, float b1, float b2, bool back) const {
  const auto level = levels_.find(triangle);
  if (level == levels_.end()) return kNone;
  const float n = float(1u << level->second);
  const float u = std::clamp(b1, 0.0f, 1.0f) * n, v = std::clamp(b2, 0.0f, 1.0f) * n;
  const uint32_t i = uint32_t(std::clamp(std::floor(u), 0.0f, n - 1.0f));
  const uint32_t j = uint32_t(std::clamp(std::floor(v), 0.0f, n - 1.0f));
  const bool inverted = (u - float(i)) + (v - float(j)) > 1.0f;
  auto found = patches_.find(key(triangle, back, i, j, inverted));
  if (found == patches_.end() && inverted) {  // on the lattice's outer edge: the upright one
    found = patches_.find(key(triangle, back, i, j, false));
  }
  return found == patches_.end() ? kNone : found->second;
}

size_t PatchLocator::memory_bytes() const {
  return (patches_.size() * (sizeof(uint64_t) + sizeof(uint32_t) + 2 * sizeof(void*))) +
         levels_.size() * (sizeof(uint32_t) + sizeof(uint16_t) + 2 * sizeof(void*));
}

}  // namespace bakegi::antiradiance
