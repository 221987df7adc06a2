#include "solvers/antiradiance/coincident_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace bakegi::antiradiance {
namespace {

// Normals agree when their components agree to this (about 0.06 degrees).
constexpr float kNormalQuantum = 1e-3f;
// Planes agree when their offsets agree to this fraction of the scene's extent.
constexpr float kRelativePlaneTolerance = 1e-4f;

struct PlaneKey {
  std::array<int32_t, 3> normal;  // the quantized normal, turned to a canonical sign
  float offset;                   // distance of the plane from the origin along it
  bool flipped;                   // the triangle faces against the canonical normal
};

PlaneKey plane_key(const Triangle& t) {
  glm::vec3 n = t.face_normal;
  // Canonical sign: the first clearly non-zero component positive.
  const int axis = std::abs(n.x) > 1e-6f ? 0 : (std::abs(n.y) > 1e-6f ? 1 : 2);
  const bool flipped = n[axis] < 0.0f;
  if (flipped) n = -n;
  const glm::vec3 centroid = (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
  return {{int32_t(std::lround(n.x / kNormalQuantum)), int32_t(std::lround(n.y / kNormalQuantum)),
           int32_t(std::lround(n.z / kNormalQuantum))},
          glm::dot(n, centroid),
          flipped};
}

// Whether point p (in t's plane, within tolerance) lies inside triangle t.
bool covers(const Triangle& t, const glm::vec3& p) {
  const glm::vec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = p - t.p[0];
  const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const float d1 = glm::dot(d, e1), d2 = glm::dot(d, e2);
  const float det = d11 * d22 - d12 * d12;
  if (!(det > 0.0f)) return false;
  const float b1 = (d22 * d1 - d12 * d2) / det, b2 = (d11 * d2 - d12 * d1) / det;
  constexpr float kSlack = -1e-4f;
  return b1 >= kSlack && b2 >= kSlack && b1 + b2 <= 1.0f - kSlack;
}


// Marks the triangles of `from` whose centroid one of `by` covers. `by` is hashed into a
// uniform grid over its bounding boxes (cells of its largest edge), so a plane of a million
// triangles costs a million lookups, not a million squared comparisons.
void mark_covered(const Scene& scene, const std::vector<uint32_t>& from,
                  const std::vector<uint32_t>& by, std::vector<uint8_t>& backed) {
  if (from.empty() || by.empty()) return;
  float cell = 0.0f;
  for (uint32_t j : by) {
    const Triangle& t = scene.triangles[j];
    for (int e = 0; e < 3; ++e) cell = std::max(cell, glm::length(t.p[(e + 1) % 3] - t.p[e]));
  }
  if (!(cell > 0.0f) || !std::isfinite(cell)) return;
  auto key = [cell](int64_t x, int64_t y, int64_t z) {
    return uint64_t(x * 73856093) ^ uint64_t(y * 19349663) ^ uint64_t(z * 83492791);
  };
  auto cell_of = [cell](float v) { return int64_t(std::floor(v / cell)); };
  std::unordered_multimap<uint64_t, uint32_t> grid;
  grid.reserve(by.size() * 2);
  for (uint32_t j : by) {
    const Triangle& t = scene.triangles[j];
    const glm::vec3 lo = glm::min(glm::min(t.p[0], t.p[1]), t.p[2]);
    const glm::vec3 hi = glm::max(glm::max(t.p[0], t.p[1]), t.p[2]);
    // A triangle's box spans at most two cells per axis (no edge is longer than a cell).
    for (int64_t x = cell_of(lo.x); x <= cell_of(hi.x); ++x)
      for (int64_t y = cell_of(lo.y); y <= cell_of(hi.y); ++y)
        for (int64_t z = cell_of(lo.z); z <= cell_of(hi.z); ++z) grid.emplace(key(x, y, z), j);
  }
  for (uint32_t i : from) {
    const Triangle& t = scene.triangles[i];
    const glm::vec3 c = (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
    const auto range = grid.equal_range(key(cell_of(c.x), cell_of(c.y), cell_of(c.z)));
    for (auto it = range.first; it != range.second; ++it) {
      if (covers(scene.triangles[it->second], c)) {
        backed[i] = 1;
        break;
      }
    }
  }
}

}  // namespace

std::vector<uint8_t> backed_by_coincident_face(const Scene& scene) {
  const size_t count = scene.triangles.size();
  std::vector<uint8_t> backed(count, 0);
  std::vector<PlaneKey> keys(count);
  for (size_t i = 0; i < count; ++i) keys[i] = plane_key(scene.triangles[i]);
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (keys[a].normal != keys[b].normal) return keys[a].normal < keys[b].normal;
    return keys[a].offset < keys[b].offset;
  });
  const float tolerance = kRelativePlaneTolerance * std::max(scene.extent(), 1e-3f);
  // Runs of one normal whose consecutive offsets lie within `tolerance`: one plane (a chain
  // of near-equal offsets); within it each side is checked against the other.
  std::vector<uint32_t> front, back;
  for (size_t begin = 0; begin < count;) {
    size_t end = begin + 1;
    while (end < count && keys[order[end]].normal == keys[order[begin]].normal &&
           keys[order[end]].offset - keys[order[end - 1]].offset <= tolerance) {
      ++end;
    }
    front.clear();
    back.clear();
    for (size_t k = begin; k < end; ++k) (keys[order[k]].flipped ? back : front).push_back(order[k]);
    mark_covered(scene, front, back, backed);
    mark_covered(scene, back, front, backed);
    begin = end;
  }
  return backed;
}

}  // namespace bakegi::antiradiance
