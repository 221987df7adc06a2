// Small input triangles grouped into one patch each (model no more than the scene needs).
// The element count of antiradiance should follow the patch size, not the tessellation: a
// floor of a million triangles, a 10,000-triangle chair, a tessellated column are each a
// handful of patches of the chosen size, while a 2-triangle wall is still split
// (element_hierarchy.h). Each group becomes one planar patch with the group's total area, its
// area-weighted mean normal and albedo; its light is what the group's triangles receive on
// average (direct light is sampled over the members, direct_initialization.h).
//
// Groups are formed within cubic cells of edge `cell` (a triangle belongs to the cell of its
// centroid) and within one surface (mesh and material: the output interpolates among patches
// of one surface). Inside a cell, triangles are split further by normal, greedily: the first
// unassigned triangle (in index order) opens a group, every unassigned one whose face normal
// is within kGroupNormalCosine of that seed's joins it. A flat surface is one group per cell;
// a curved one is cut where it turns by more than ~37°; foliage with leaves every way becomes
// a few groups per cell (caps of 37° cover the sphere about ten times), each close enough to
// planar for the local pass's single normal. The grid's origin is offset from the scene's
// bounds by an irrational fraction of a cell so that walls at the bounds do not lie on cell
// borders, where rounding would deal their triangles to two cells.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace bakegi::antiradiance {

// cos 36.9°: the largest angle between a group's seed normal and a member's.
inline constexpr float kGroupNormalCosine = 0.8f;

struct TriangleGroups {
  // Group g holds triangles members[offsets[g] .. offsets[g + 1]), ascending; groups are in
  // order of their first member.
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> members;

  size_t size() const { return offsets.size() - 1; }
  std::span<const uint32_t> group(size_t g) const {
    return std::span<const uint32_t>(members).subspan(offsets[g], offsets[g + 1] - offsets[g]);
  }
};

// What grouping needs of a triangle (or of a piece of one: element_hierarchy.h cuts slivers
// into pieces first).
struct GroupCandidate {
  glm::vec3 centroid{0.0f};
  glm::vec3 normal{0.0f};  // unit face normal
  uint32_t mesh = 0, material = 0;
};

// Groups candidates by cell of edge `cell` (the grid placed from `bounds_min`), surface and
// normal as described above; the groups hold indices into `candidates`, and a candidate's
// index breaks every tie, so the result depends on the candidates' order only through their
// indices. `cell` must be positive and finite.
TriangleGroups group_candidates(std::span<const GroupCandidate> candidates, glm::vec3 bounds_min,
                                float cell);

// The same for whole triangles (indices into scene.triangles, any order); the groups hold
// triangle indices and do not depend on the order given.
TriangleGroups group_triangles(const Scene& scene, std::span<const uint32_t> triangles,
                               float cell);

}  // namespace bakegi::antiradiance
