#include "solvers/antiradiance/triangle_grouping.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace bakegi::antiradiance {

namespace {

// 1 / golden ratio: walls at the scene's bounds sit at 0.382 of a cell, not on its border.
constexpr float kGridOffsetInCells = 0.381966f;

struct Keyed {
  uint32_t mesh, material;
  int64_t cell[3];
  uint32_t candidate;  // index into the candidates: breaks ties, so the order is total

  auto key() const { return std::tie(mesh, material, cell[0], cell[1], cell[2]); }
};

int64_t cell_index(float coordinate, float origin, float cell) {
  // Clamped so that absurd coordinates (validated scenes keep |x| < 1e12) stay integers.
  const double i = std::floor((double(coordinate) - double(origin)) / double(cell));
  return int64_t(std::clamp(i, -9.0e15, 9.0e15));
}

}  // namespace

TriangleGroups group_candidates(std::span<const GroupCandidate> candidates, glm::vec3 bounds_min,
                                float cell) {
  TriangleGroups groups;
  if (candidates.empty()) return groups;
  const glm::vec3 origin = bounds_min - kGridOffsetInCells * cell;
  std::vector<Keyed> keyed(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) {
    const GroupCandidate& c = candidates[i];
    keyed[i] = {c.mesh,
                c.material,
                {cell_index(c.centroid.x, origin.x, cell), cell_index(c.centroid.y, origin.y, cell),
                 cell_index(c.centroid.z, origin.z, cell)},
                uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return std::tie(a.mesh, a.material, a.cell[0], a.cell[1], a.cell[2], a.candidate) <
           std::tie(b.mesh, b.material, b.cell[0], b.cell[1], b.cell[2], b.candidate);
  });
  // Per cell: greedy normal cones. `open` holds the cell's candidates not yet in a group.
  std::vector<uint32_t> open, rest;
  struct Group {
    uint32_t first;
    std::vector<uint32_t> members;
  };
  std::vector<Group> found;
  for (size_t begin = 0; begin < keyed.size();) {
    size_t end = begin + 1;
    while (end < keyed.size() && keyed[end].key() == keyed[begin].key()) ++end;
    open.clear();
    for (size_t i = begin; i < end; ++i) open.push_back(keyed[i].candidate);  // ascending
    while (!open.empty()) {
      const glm::vec3 seed = candidates[open.front()].normal;
      Group group{open.front(), {}};
      rest.clear();
      for (uint32_t c : open) {
        if (c == open.front() || glm::dot(candidates[c].normal, seed) >= kGroupNormalCosine) {
          group.members.push_back(c);
        } else {
          rest.push_back(c);
        }
      }
      found.push_back(std::move(group));
      open.swap(rest);
    }
    begin = end;
  }
  std::sort(found.begin(), found.end(),
            [](const Group& a, const Group& b) { return a.first < b.first; });
  groups.members.reserve(candidates.size());
  groups.offsets.reserve(found.size() + 1);
  for (const Group& group : found) {
    groups.members.insert(groups.members.end(), group.members.begin(), group.members.end());
    groups.offsets.push_back(uint32_t(groups.members.size()));
  }
  return groups;
}

TriangleGroups group_triangles(const Scene& scene, std::span<const uint32_t> triangles,
                               float cell) {
  std::vector<uint32_t> sorted(triangles.begin(), triangles.end());
  std::sort(sorted.begin(), sorted.end());
  std::vector<GroupCandidate> candidates(sorted.size());
  for (size_t i = 0; i < sorted.size(); ++i) {
    const Triangle& t = scene.triangles[sorted[i]];
    candidates[i] = {(t.p[0] + t.p[1] + t.p[2]) / 3.0f, t.face_normal, t.mesh, t.material};
  }
  TriangleGroups groups = group_candidates(candidates, scene.bounds_min, cell);
  for (uint32_t& m : groups.members) m = sorted[m];
  return groups;
}

}  // namespace bakegi::antiradiance
