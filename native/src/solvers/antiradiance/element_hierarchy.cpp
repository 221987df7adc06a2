#include "solvers/antiradiance/element_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "scene/phong_lobe.h"
#include "scene/triangle_geometry.h"
#include "solvers/antiradiance/back_sides.h"
#include "solvers/antiradiance/triangle_bisection.h"
#include "solvers/antiradiance/triangle_grouping.h"
#include "util/error.h"

namespace bakegi::antiradiance {

namespace {

// Element indices are 32-bit; kNoElement is reserved.
constexpr uint64_t kHardElementLimit = uint64_t(kNoElement) - 1;

float longest_edge(const Triangle& t) {
  return std::max(
      {glm::length(t.p[1] - t.p[0]), glm::length(t.p[2] - t.p[1]), glm::length(t.p[0] - t.p[2])});
}

uint64_t saturating_add(uint64_t a, uint64_t b) {
  return a > std::numeric_limits<uint64_t>::max() - b ? std::numeric_limits<uint64_t>::max()
                                                      : a + b;
}

void check_max_edge(float max_edge) {
  if (!(max_edge > 0.0f) || !std::isfinite(max_edge)) {
    std::ostringstream message;
    message << "antiradiance: the patch size (max_edge) must be a positive number of metres, got "
            << max_edge;
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, message.str());
  }
}

// A patch before the tree is built: everything but its element index.
struct PatchSeed {
  Patch patch;
  glm::vec3 center;
  float area;
};

// Calls f(corner) for every corner of the patch: its own three, or its members' for a merged
// patch (the element's bounds and radius cover all of them).
template <typename F>
void for_each_corner(const Patch& patch, const std::vector<MemberTriangle>& members, F&& f) {
  if (patch.member_count == 0) {
    for (const glm::vec3& corner : patch.corners) f(corner);
    return;
  }
  for (uint32_t m = patch.first_member; m < patch.first_member + patch.member_count; ++m) {
    for (const glm::vec3& corner : members[m].corners) f(corner);
  }
}

// A grouping candidate: a whole small triangle (code 0) or a piece of a sliver (triangle_bisection.h).
struct Piece {
  uint32_t triangle = 0;
  uint32_t code = 0;
  float area = 0.0f;
  glm::vec3 corners[3];
  glm::vec2 centroid_uv{1.0f / 3.0f};  // barycentrics of the piece's centroid in the triangle
};

glm::vec3 centroid_of(const Piece& piece) {
  return (piece.corners[0] + piece.corners[1] + piece.corners[2]) / 3.0f;
}

// One sliver piece as a patch on its own.
PatchSeed piece_seed(const Scene& scene, const Piece& piece, uint32_t surface) {
  const Triangle& t = scene.triangles[piece.triangle];
  PatchSeed seed;
  Patch& patch = seed.patch;
  std::copy(piece.corners, piece.corners + 3, patch.corners);
  patch.normal = t.face_normal;
  const glm::vec3 shading = at_barycentrics(t.n, piece.centroid_uv);
  const float length = glm::length(shading);
  patch.shading_normal = length > 1e-6f ? shading / length : patch.normal;
  patch.albedo = scene.albedo_at(t, piece.centroid_uv.x, piece.centroid_uv.y);
  patch.glossy = scene.material_of(t).glossy;
  patch.glossy_exponent = scene.material_of(t).glossy_exponent;
  patch.triangle = piece.triangle;
  patch.surface = surface;
  patch.sliver_piece = piece.code;
  seed.center = centroid_of(piece);
  seed.area = piece.area;
  return seed;
}

// One patch for a group of pieces (triangle_grouping.h); appends them to `members`.
PatchSeed merged_seed(const Scene& scene, const std::vector<Piece>& pieces,
                      std::span<const uint32_t> group, uint32_t surface,
                      std::vector<MemberTriangle>& members) {
  PatchSeed seed;
  Patch& patch = seed.patch;
  patch.first_member = uint32_t(members.size());
  patch.member_count = uint32_t(group.size());
  double area = 0.0;
  glm::dvec3 centroid_sum(0.0), normal_sum(0.0), shading_sum(0.0), albedo_sum(0.0);
  for (uint32_t index : group) {
    const Piece& piece = pieces[index];
    const Triangle& t = scene.triangles[piece.triangle];
    MemberTriangle member;
    member.triangle = piece.triangle;
    member.code = piece.code;
    member.area = piece.area;
    std::copy(piece.corners, piece.corners + 3, member.corners);
    members.push_back(member);
    const double a = double(piece.area);
    area += a;
    centroid_sum += a * glm::dvec3(centroid_of(piece));
    normal_sum += a * glm::dvec3(t.face_normal);
    shading_sum += a * glm::dvec3(at_barycentrics(t.n, piece.centroid_uv));
    albedo_sum += a * glm::dvec3(scene.albedo_at(t, piece.centroid_uv.x, piece.centroid_uv.y));
  }
  const glm::dvec3 mean_centroid = area > 0.0 ? centroid_sum / area : centroid_sum;
  // The centre: the point of the members nearest their area-weighted centroid. On a planar
  // group that is the centroid itself, whichever way its quads were triangulated (a mirrored
  // copy of a mesh splits them along the other diagonal and must bake the same); on a curved
  // one, whose centroid lies inside the object, a point on the surface. `triangle` and
  // `corners` are the member it lies on (first in order on ties).
  double nearest = std::numeric_limits<double>::infinity();
  for (uint32_t index : group) {
    const Piece& piece = pieces[index];
    const glm::dvec3 q = closest_point_on_triangle(mean_centroid, glm::dvec3(piece.corners[0]),
                                                   glm::dvec3(piece.corners[1]),
                                                   glm::dvec3(piece.corners[2]));
    const double d = glm::dot(q - mean_centroid, q - mean_centroid);
    if (d < nearest) {
      nearest = d;
      seed.center = glm::vec3(q);
      patch.triangle = piece.triangle;
      std::copy(piece.corners, piece.corners + 3, patch.corners);
    }
  }
  const Triangle& representative = scene.triangles[patch.triangle];
  // Members' normals lie within kGroupNormalCosine of the group's seed, so the sum is long.
  const double normal_length = glm::length(normal_sum);
  patch.normal = normal_length > 0.0 ? glm::vec3(normal_sum / normal_length)
                                     : representative.face_normal;
  const double shading_length = glm::length(shading_sum);
  patch.shading_normal =
      shading_length > 1e-6 * area ? glm::vec3(shading_sum / shading_length) : patch.normal;
  patch.albedo = area > 0.0 ? glm::vec3(albedo_sum / area) : glm::vec3(0.0f);
  // One surface is one material: the members share its lobe (folded later like any patch's).
  patch.glossy = scene.material_of(representative).glossy;
  patch.glossy_exponent = scene.material_of(representative).glossy_exponent;
  patch.surface = surface;
  seed.area = float(area);
  return seed;
}

// Repeated 4-way midpoint subdivision of one triangle, done in its barycentric (b1, b2)
// coordinates so that albedo and shading normals are evaluated where the patch lies.
class TriangleSubdivider {
 public:
  TriangleSubdivider(const Scene& scene, uint32_t triangle_index, uint32_t surface, int level,
                     std::vector<PatchSeed>& out)
      : scene_(scene),
        triangle_(scene.triangles[triangle_index]),
        triangle_index_(triangle_index),
        surface_(surface),
        level_(level),
        // Midpoint subdivision splits a triangle into four of exactly a quarter of its area;
        // dividing the source area keeps the patch areas summing to it without rounding drift.
        patch_area_(float(double(triangle_.area) / std::ldexp(1.0, 2 * level))),
        out_(out) {}

  void run() { split({0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}, level_); }

 private:
  glm::vec3 position(glm::vec2 b) const { return at_barycentrics(triangle_.p, b); }

  void split(glm::vec2 a, glm::vec2 b, glm::vec2 c, int depth) {
    if (depth == 0) {
      emit(a, b, c);
      return;
    }
    const glm::vec2 ab = 0.5f * (a + b), bc = 0.5f * (b + c), ca = 0.5f * (c + a);
    // All four children keep the parent's winding, so the face normal stays valid.
    split(a, ab, ca, depth - 1);
    split(ab, b, bc, depth - 1);
    split(ca, bc, c, depth - 1);
    split(ab, bc, ca, depth - 1);
  }

  void emit(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
    const glm::vec2 centroid = (a + b + c) / 3.0f;
    PatchSeed seed;
    Patch& patch = seed.patch;
    patch.corners[0] = position(a);
    patch.corners[1] = position(b);
    patch.corners[2] = position(c);
    patch.normal = triangle_.face_normal;
    // The mean of the linearly interpolated shading normal over the patch is its value at
    // the centroid.
    const glm::vec3 shading = at_barycentrics(triangle_.n, centroid);
    const float shading_length = glm::length(shading);
    patch.shading_normal = shading_length > 1e-6f ? shading / shading_length : patch.normal;
    patch.albedo = scene_.albedo_at(triangle_, centroid.x, centroid.y);
    patch.glossy = scene_.material_of(triangle_).glossy;
    patch.glossy_exponent = scene_.material_of(triangle_).glossy_exponent;
    patch.triangle = triangle_index_;
    patch.surface = surface_;
    patch.subdivision_level = uint16_t(level_);
    seed.center = position(centroid);
    seed.area = patch_area_;
    out_.push_back(seed);
  }

  const Scene& scene_;
  const Triangle& triangle_;
  uint32_t triangle_index_;
  uint32_t surface_;
  int level_;
  float patch_area_;
  std::vector<PatchSeed>& out_;
};

// Builds the binary cluster tree over the seeds by median split along the longest axis of
// the patch centroids' bounds, writing elements in pre-order.
class TreeBuilder {
 public:
  TreeBuilder(std::vector<PatchSeed>& seeds, const std::vector<MemberTriangle>& members,
              std::vector<Element>& elements, std::vector<Patch>& patches)
      : seeds_(seeds), members_(members), elements_(elements), patches_(patches) {}

  void run() {
    std::vector<uint32_t> order(seeds_.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    elements_.reserve(2 * seeds_.size() - 1);
    patches_.reserve(seeds_.size());
    emit(order.data(), order.data() + order.size(), kNoElement, 0);
  }

 private:
  uint32_t emit(uint32_t* begin, uint32_t* end, uint32_t parent, uint16_t level) {
    const uint32_t index = uint32_t(elements_.size());
    elements_.emplace_back();
    const size_t count = size_t(end - begin);
    if (count == 1) {
      emit_patch(index, seeds_[*begin], parent, level);
      return index;
    }

    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const uint32_t* s = begin; s != end; ++s) {
      lo = glm::min(lo, seeds_[*s].center);
      hi = glm::max(hi, seeds_[*s].center);
    }
    const glm::vec3 size = hi - lo;
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    uint32_t* middle = begin + count / 2;
    // Ties broken by seed index so that the layout does not depend on the library's
    // nth_element.
    std::nth_element(begin, middle, end, [&](uint32_t a, uint32_t b) {
      const float ca = seeds_[a].center[axis], cb = seeds_[b].center[axis];
      return ca < cb || (ca == cb && a < b);
    });

    const uint32_t first = emit(begin, middle, index, uint16_t(level + 1));
    const uint32_t second = emit(middle, end, index, uint16_t(level + 1));

    Element& cluster = elements_[index];
    const Element& a = elements_[first];
    const Element& b = elements_[second];
    cluster.parent = parent;
    cluster.level = level;
    cluster.is_patch = false;
    cluster.first_child = first;
    cluster.child_count = 2;
    cluster.subtree_end = uint32_t(elements_.size());
    // Sum in double: a cluster's area is compared with the sum of its children exactly.
    const double area = double(a.area) + double(b.area);
    cluster.area = float(area);
    cluster.center = glm::vec3(
        (glm::dvec3(a.center) * double(a.area) + glm::dvec3(b.center) * double(b.area)) / area);
    cluster.bounds_min = glm::min(a.bounds_min, b.bounds_min);
    cluster.bounds_max = glm::max(a.bounds_max, b.bounds_max);
    // The tightest sphere about the centre: the farthest patch corner of the subtree.
    float radius2 = 0.0f;
    for (uint32_t e = index + 1; e < cluster.subtree_end; ++e) {
      if (!elements_[e].is_patch) continue;
      for_each_corner(patches_[elements_[e].patch], members_, [&](const glm::vec3& corner) {
        const glm::vec3 d = corner - cluster.center;
        radius2 = std::max(radius2, glm::dot(d, d));
      });
    }
    cluster.radius = std::sqrt(radius2);
    return index;
  }

  void emit_patch(uint32_t index, const PatchSeed& seed, uint32_t parent, uint16_t level) {
    Element& element = elements_[index];
    element.center = seed.center;
    element.area = seed.area;
    element.parent = parent;
    element.level = level;
    element.is_patch = true;
    element.subtree_end = index + 1;
    element.patch = uint32_t(patches_.size());
    element.bounds_min = element.bounds_max = seed.patch.corners[0];
    float radius2 = 0.0f;
    for_each_corner(seed.patch, members_, [&](const glm::vec3& corner) {
      element.bounds_min = glm::min(element.bounds_min, corner);
      element.bounds_max = glm::max(element.bounds_max, corner);
      const glm::vec3 d = corner - seed.center;
      radius2 = std::max(radius2, glm::dot(d, d));
    });
    element.radius = std::sqrt(radius2);
    patches_.push_back(seed.patch);
    patches_.back().element = index;
  }

  std::vector<PatchSeed>& seeds_;
  const std::vector<MemberTriangle>& members_;
  std::vector<Element>& elements_;
  std::vector<Patch>& patches_;
};

}  // namespace

float default_max_edge(const Scene& scene) {
  // Coarse: the output's near-field gather (near_field_gather.h) resolves what changes within
  // a patch near other surfaces, so finer patches mostly add links. On the Cornell box,
  // extent / 32 (split once) gave 4.5% in 1.8 s at 192 bins, extent / 16 (whole triangles)
  // 5.1% in 0.6 s, and 4.3% in 1.0 s at 300 bins.
  return scene.extent() / 16.0f;
}

int subdivision_level(float longest_edge, float max_edge) {
  int level = 0;
  while (longest_edge > max_edge && level < kMaxSubdivisionLevel) {
    longest_edge *= 0.5f;  // exact in binary floating point
    ++level;
  }
  return level;
}

namespace {

// Triangles with a longest edge up to this fraction of the patch size group.
constexpr float kGroupedEdge = 0.25f;

// A triangle whose longest edge is more than this many times its height over that edge is a
// sliver (equilateral: 1.15; a right isosceles triangle on its hypotenuse: 2).
constexpr float kSliverAspect = 4.0f;

// Counting stops beyond this many patches (the count then saturates): more than any budget
// allows, and an absurdly small patch size costs no time to refuse.
constexpr uint64_t kCountedPatchLimit = uint64_t(1) << 27;

// How the triangles become patches at one patch size: split 4-way or whole (leaves[i] > 0
// patches at level[i]), or pieces to group (leaves[i] == 0: a small triangle is one piece, a
// sliver is bisected into pieces of the cell size). Pieces are in triangle order.
struct PatchPlan {
  std::vector<uint64_t> leaves;
  std::vector<uint8_t> level;
  std::vector<Piece> pieces;
  TriangleGroups groups;    // of pieces
  bool saturated = false;   // more than kCountedPatchLimit patches or pieces
};

PatchPlan plan_patches(const Scene& scene, float max_edge) {
  check_max_edge(max_edge);
  const float cell = 0.5f * max_edge;
  PatchPlan plan;
  plan.leaves.assign(scene.triangles.size(), 0);
  plan.level.assign(scene.triangles.size(), 0);
  std::vector<GroupCandidate> candidates;
  uint64_t total = 0;
  const auto add_piece = [&](const Piece& piece) {
    const Triangle& t = scene.triangles[piece.triangle];
    plan.pieces.push_back(piece);
    candidates.push_back({centroid_of(piece), t.face_normal, t.mesh, t.material});
  };
  for (uint32_t i = 0; i < scene.triangles.size() && !plan.saturated; ++i) {
    const Triangle& t = scene.triangles[i];
    // Only triangles well under the patch size group: one a little smaller is as good a
    // patch on its own (grouping the suite's 12,960-triangle Cornell box at its 0.11 m
    // triangles took it from 4.0% to 5.0%, and a maze of 0.1 m walls from 75% to 115%).
    if (longest_edge(t) <= kGroupedEdge * max_edge) {
      Piece piece;
      piece.triangle = i;
      piece.area = t.area;
      std::copy(t.p, t.p + 3, piece.corners);
      add_piece(piece);
      ++total;
      continue;
    }
    // 4-way midpoint splits keep a triangle's shape (what the solver's tests and tuning are
    // for) but halve every edge: a sliver (longest edge more than kSliverAspect times its
    // height over that edge) would become 4^k needles. It is bisected into pieces of the cell
    // size instead (triangle_bisection.h), which group with their neighbours.
    const float edge = longest_edge(t);
    const bool sliver = edge * edge > kSliverAspect * 2.0f * t.area;
    if (!sliver) {
      const int level = subdivision_level(edge, max_edge);
      plan.level[i] = uint8_t(level);
      plan.leaves[i] = uint64_t(1) << (2 * level);
      total += plan.leaves[i];
      plan.saturated = total > kCountedPatchLimit;
      continue;
    }
    total += bisection_piece_count(t, cell, kCountedPatchLimit - std::min(total, kCountedPatchLimit));
    plan.saturated = total > kCountedPatchLimit;
    if (plan.saturated) break;
    bisect_triangle(t, cell, [&](const BisectionPiece& cut) {
      Piece piece;
      piece.triangle = i;
      piece.code = cut.code;
      for (int c = 0; c < 3; ++c) piece.corners[c] = at_barycentrics(t.p, cut.corners[c]);
      piece.area = float(double(t.area) / std::ldexp(1.0, cut.depth));
      piece.centroid_uv = (cut.corners[0] + cut.corners[1] + cut.corners[2]) / 3.0f;
      add_piece(piece);
    });
  }
  if (!plan.saturated) plan.groups = group_candidates(candidates, scene.bounds_min, cell);
  return plan;
}

// A merged patch gets a back side when most of its area (by its members) would have one.
bool group_has_back_side(const std::vector<Piece>& pieces, std::span<const uint32_t> group,
                         const std::vector<uint8_t>& back_side) {
  double with = 0.0, all = 0.0;
  for (uint32_t p : group) {
    all += double(pieces[p].area);
    if (back_side[pieces[p].triangle]) with += double(pieces[p].area);
  }
  return with > 0.0 && with >= 0.5 * all;
}

}  // namespace

PatchCount::PatchCount(const Scene& scene) : scene_(scene) {}

const PatchCount::Counts& PatchCount::counts(float max_edge) const {
  for (const auto& [edge, counts] : known_) {
    if (edge == max_edge) return counts;
  }
  const PatchPlan plan = plan_patches(scene_, max_edge);
  Counts counts;
  for (uint32_t i = 0; i < scene_.triangles.size(); ++i) {
    if (plan.leaves[i] == 0) continue;
    const uint64_t patches = plan.leaves[i];
    counts.front = saturating_add(counts.front, patches);
    const uint64_t sides = on_open_mesh(scene_, scene_.triangles[i]) ? 2 : 1;
    counts.with_back = saturating_add(counts.with_back, sides * patches);
  }
  for (size_t g = 0; g < plan.groups.size(); ++g) {
    const std::span<const uint32_t> group = plan.groups.group(g);
    bool open = false;
    for (uint32_t p : group) {
      open = open || on_open_mesh(scene_, scene_.triangles[plan.pieces[p].triangle]);
    }
    counts.front += 1;
    counts.with_back += open ? 2 : 1;
    if (group.size() > 1) counts.members += group.size();
  }
  if (plan.saturated) {
    counts.front = counts.with_back = std::numeric_limits<uint64_t>::max();
  }
  known_.emplace_back(max_edge, counts);
  return known_.back().second;
}

uint64_t PatchCount::patches(float max_edge, bool include_back_sides) const {
  const Counts& c = counts(max_edge);
  return include_back_sides ? c.with_back : c.front;
}

uint64_t PatchCount::elements(float max_edge, bool include_back_sides) const {
  const uint64_t patches = this->patches(max_edge, include_back_sides);
  if (patches == 0) return 0;
  return patches > std::numeric_limits<uint64_t>::max() / 2 ? std::numeric_limits<uint64_t>::max()
                                                            : 2 * patches - 1;
}

uint64_t PatchCount::hierarchy_bytes(float max_edge, bool include_back_sides) const {
  const uint64_t patches = this->patches(max_edge, include_back_sides);
  const uint64_t per_patch = 2 * sizeof(Element) + sizeof(Patch);
  if (patches > std::numeric_limits<uint64_t>::max() / per_patch) {
    return std::numeric_limits<uint64_t>::max();
  }
  if (patches == 0) return 0;
  // 2 * patches - 1 elements; a merged patch and its twin share their members.
  return saturating_add(patches * per_patch - sizeof(Element),
                        counts(max_edge).members * sizeof(MemberTriangle));
}

float PatchCount::max_edge_within_budget(float max_edge, uint64_t max_elements,
                                         bool include_back_sides) const {
  check_max_edge(max_edge);
  // Each doubling splits large triangles less and merges small ones into larger cells; once a
  // cell spans the whole scene nothing changes any more.
  const float stop = 4.0f * std::max(scene_.extent(), max_edge);
  while (elements(max_edge, include_back_sides) > max_elements) {
    const float next = max_edge * 2.0f;
    if (!std::isfinite(next) || max_edge > stop) break;
    max_edge = next;
  }
  return max_edge;
}

uint64_t estimate_patches(const Scene& scene, float max_edge, bool include_back_sides) {
  return PatchCount(scene).patches(max_edge, include_back_sides);
}

uint64_t estimate_elements(const Scene& scene, float max_edge, bool include_back_sides) {
  return PatchCount(scene).elements(max_edge, include_back_sides);
}

uint64_t estimate_hierarchy_bytes(const Scene& scene, float max_edge, bool include_back_sides) {
  return PatchCount(scene).hierarchy_bytes(max_edge, include_back_sides);
}

float max_edge_within_budget(const Scene& scene, float max_edge, uint64_t max_elements) {
  return PatchCount(scene).max_edge_within_budget(max_edge, max_elements);
}

namespace {

// A lobe this wide spreads a bounce over a large part of the hemisphere, so reflecting it as
// diffuse moves little light, while the glossy local pass costs up to m²/2 per patch instead of
// 2m: Principled BSDF's defaults (roughness 0.5: exponent 7.5, ρ_g 0.086) made the Cornell box's
// iterations 3.7x slower. Energy is kept for a uniform field (the hemispherical albedo).
void fold_wide_glossy_lobes(std::vector<PatchSeed>& seeds, float below_exponent) {
  std::map<float, float> albedo_by_exponent;
  for (PatchSeed& seed : seeds) {
    Patch& patch = seed.patch;
    const float strongest = std::max({patch.glossy.x, patch.glossy.y, patch.glossy.z});
    if (!(strongest > 0.0f) || !(patch.glossy_exponent < below_exponent)) {
      continue;
    }
    auto [it, inserted] = albedo_by_exponent.try_emplace(patch.glossy_exponent, 0.0f);
    if (inserted) it->second = float(phong_hemispherical_albedo(patch.glossy_exponent));
    patch.albedo += it->second * patch.glossy;
    patch.glossy = glm::vec3(0.0f);
    patch.glossy_exponent = 0.0f;
  }
}

}  // namespace

namespace {

struct PatchCounts {
  std::vector<uint32_t> group_at;   // the group starting at each piece, else kNoElement
  std::vector<uint8_t> group_back;  // per group: whether it gets a back side
  uint64_t patch_count = 0;         // saturating
};

// How many patches the plan makes (a triangle's leaves, one per group, twice with a back
// side), before any is made, so the budget can refuse first.
PatchCounts count_patches(const Scene& scene, const PatchPlan& plan,
                          const std::vector<uint8_t>& back_side) {
  const auto has_back = [&](uint32_t t) { return !back_side.empty() && back_side[t] != 0; };
  PatchCounts counts;
  // Groups are in order of their first piece.
  counts.group_at.assign(plan.pieces.size(), kNoElement);
  counts.group_back.assign(plan.groups.size(), 0);
  uint64_t patch_count = 0;
  for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
    if (plan.leaves[i] == 0) continue;
    const uint64_t sides = has_back(i) ? 2 : 1;
    patch_count = saturating_add(patch_count, sides * plan.leaves[i]);
  }
  if (plan.saturated) patch_count = std::numeric_limits<uint64_t>::max();
  for (size_t g = 0; g < plan.groups.size(); ++g) {
    const std::span<const uint32_t> group = plan.groups.group(g);
    counts.group_at[group.front()] = uint32_t(g);
    counts.group_back[g] =
        !back_side.empty() && group_has_back_side(plan.pieces, group, back_side);
    patch_count += counts.group_back[g] ? 2 : 1;
  }
  counts.patch_count = patch_count;
  return counts;
}

// Refuses (OUT_OF_MEMORY, naming a patch size that fits) a hierarchy of more elements than
// the budget: a binary tree over n patches has 2n - 1 elements.
void check_element_budget(const Scene& scene, float max_edge, uint64_t patch_count,
                          const HierarchyOptions& options) {
  const uint64_t elements = patch_count > std::numeric_limits<uint64_t>::max() / 2
                                ? std::numeric_limits<uint64_t>::max()
                                : 2 * patch_count - 1;
  const uint64_t budget = options.max_elements > 0
                              ? std::min(options.max_elements, kHardElementLimit)
                              : kHardElementLimit;
  if (elements > budget) {
    std::ostringstream message;
    message << "antiradiance: patches of at most " << max_edge << " m would make " << elements
            << " elements, more than the budget of " << budget << "; a patch size of "
            << PatchCount(scene).max_edge_within_budget(max_edge, budget) << " m fits";
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, message.str());
  }
}

}  // namespace

ElementHierarchy::ElementHierarchy(const Scene& scene, const HierarchyOptions& options) {
  max_edge_ = options.max_edge == 0.0f ? default_max_edge(scene) : options.max_edge;
  check_max_edge(max_edge_);
  if (scene.triangles.empty()) {
    throw Error(BAKEGI_ERROR_INVALID_SCENE, "antiradiance: the scene has no triangles");
  }

  const PatchPlan plan = plan_patches(scene, max_edge_);
  // Which triangles get a back side decides the exact count, so it comes first (cheap: a few
  // rays per triangle of an open mesh).
  std::vector<uint8_t> back_side;
  if (options.back_sides != nullptr) back_side = exposed_back_sides(scene, *options.back_sides);
  const auto has_back = [&](uint32_t t) { return !back_side.empty() && back_side[t] != 0; };
  const PatchCounts counts = count_patches(scene, plan, back_side);
  const std::vector<uint32_t>& group_at = counts.group_at;
  const std::vector<uint8_t>& group_back = counts.group_back;
  const uint64_t patch_count = counts.patch_count;
  check_element_budget(scene, max_edge_, patch_count, options);

  // (mesh, material, side) -> id
  std::map<std::tuple<uint32_t, uint32_t, bool>, uint32_t> surfaces;
  std::vector<PatchSeed> seeds;
  seeds.reserve(size_t(patch_count));
  size_t member_total = 0;
  for (size_t g = 0; g < plan.groups.size(); ++g) {
    if (plan.groups.group(g).size() > 1) member_total += plan.groups.group(g).size();
  }
  members_.reserve(member_total);
  // Seeds in triangle order: a triangle's own patches, or the groups whose first piece is
  // one of its pieces, each followed by its twin.
  size_t next_piece = 0;
  for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    const auto emit = [&](auto&& make_seeds, bool twin) {
      const uint32_t surface =
          surfaces.try_emplace({t.mesh, t.material, false}, uint32_t(surfaces.size())).first->second;
      const size_t first = seeds.size();
      make_seeds(surface);
      if (!twin) return;
      const uint32_t back_surface =
          surfaces.try_emplace({t.mesh, t.material, true}, uint32_t(surfaces.size())).first->second;
      const size_t last = seeds.size();
      for (size_t s = first; s < last; ++s) {
        // The same center, bit for bit: link refinement pairs nothing.
        PatchSeed twin_seed = seeds[s];
        std::swap(twin_seed.patch.corners[1], twin_seed.patch.corners[2]);
        twin_seed.patch.normal = -twin_seed.patch.normal;
        twin_seed.patch.shading_normal = -twin_seed.patch.shading_normal;
        twin_seed.patch.surface = back_surface;
        twin_seed.patch.back_side = true;
        seeds.push_back(twin_seed);
        if (twin_seed.patch.member_count > 0) ++merged_patch_count_;
      }
      back_side_count_ += last - first;
    };
    if (plan.leaves[i] > 0) {
      emit([&](uint32_t surface) { TriangleSubdivider(scene, i, surface, plan.level[i], seeds).run(); },
           has_back(i));
      continue;
    }
    for (; next_piece < plan.pieces.size() && plan.pieces[next_piece].triangle == i; ++next_piece) {
      const uint32_t g = group_at[next_piece];
      if (g == kNoElement) continue;  // in a group seeded earlier
      const std::span<const uint32_t> group = plan.groups.group(g);
      const Piece& piece = plan.pieces[next_piece];
      emit(
          [&](uint32_t surface) {
            if (group.size() > 1) {
              seeds.push_back(merged_seed(scene, plan.pieces, group, surface, members_));
              ++merged_patch_count_;
            } else if (piece.code == 0) {
              TriangleSubdivider(scene, i, surface, 0, seeds).run();
            } else {
              seeds.push_back(piece_seed(scene, piece, surface));
            }
          },
          group_back[g] != 0);
    }
  }
  surface_count_ = uint32_t(surfaces.size());
  if (options.glossy_fold_exponent > 0.0f)
    fold_wide_glossy_lobes(seeds, options.glossy_fold_exponent);

  TreeBuilder(seeds, members_, elements_, patches_).run();
}

size_t ElementHierarchy::memory_bytes() const {
  return elements_.capacity() * sizeof(Element) + patches_.capacity() * sizeof(Patch) +
         members_.capacity() * sizeof(MemberTriangle);
}

}  // namespace bakegi::antiradiance
