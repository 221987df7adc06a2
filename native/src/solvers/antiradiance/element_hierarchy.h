// The element hierarchy of Antiradiance (paper §3.2, §4.1): input triangles subdivided into
// patches below a size threshold, small ones grouped into patches of about that size
// (triangle_grouping.h), a binary tree of clusters above them, all elements in one array in
// depth-first (pre-order) order so that push (parent -> descendants) and pull (leaves ->
// ancestors) are contiguous loops over that array.
//
// Patch sizes: a triangle whose longest edge exceeds max_edge is split 4-way until its
// patches' edges are at most max_edge. A sliver (a long thin triangle, as fan triangulations
// of n-gons make them: 4-way splits would turn it into 4^k needles) is instead bisected into
// pieces no longer than max_edge / 2 (triangle_bisection.h), which group like small
// triangles. A triangle whose longest edge is at most max_edge / 4 joins a group of small
// triangles of its surface in a cell of edge max_edge / 2 (triangle_grouping.h), so a merged
// patch spans at most about max_edge too. The rest are a patch each. The element count thus
// follows the patch size and no longer the tessellation (the 131k-triangle living room had
// 388,911 elements unsplit; 22,449 grouped at the default size).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"
#include "scene/scene.h"

namespace bakegi::antiradiance {

inline constexpr uint32_t kNoElement = 0xffffffffu;

// One node of the hierarchy, cluster or patch. Subtree of element i = [i, subtree_end):
// pre-order puts a node before all of its descendants, so parent < child always holds and
// the first child (if any) is i + 1; the next sibling of child c is elements[c].subtree_end.
struct Element {
  glm::vec3 center{0.0f};  // patch: centroid; cluster: area-weighted mean of its patches' centroids
  float radius = 0.0f;     // bounding sphere about `center` of every patch corner in the subtree
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // of every patch corner in the subtree
  float area = 0.0f;                             // patch area, or sum over the children
  uint32_t parent = kNoElement;                  // kNoElement for the root
  uint32_t first_child = kNoElement;             // kNoElement for patches
  uint32_t child_count = 0;                      // 2 for clusters, 0 for patches
  uint32_t subtree_end = 0;                      // one past the last element of the subtree
  uint32_t patch = kNoElement;  // index into ElementHierarchy::patches(), patches only
  uint16_t level = 0;           // depth below the root (root: 0)
  bool is_patch = false;
};

// A triangle that belongs to a merged patch: a whole input triangle, or a piece of a sliver
// (slivers are cut into pieces about as long as the grouping cell, which then group).
struct MemberTriangle {
  glm::vec3 corners[3];   // world positions, counter-clockwise like the input triangle
  uint32_t triangle = 0;  // index into Scene::triangles
  uint32_t code = 0;      // 0: the whole triangle; else its piece code (triangle_bisection.h)
  float area = 0.0f;
};

// What only patches carry (clusters need no normal: the paper's oracle uses none).
struct Patch {
  glm::vec3 corners[3];            // counter-clockwise around `normal`
  glm::vec3 normal{0.0f};          // unit face normal of the source triangle
  glm::vec3 shading_normal{0.0f};  // unit mean of the interpolated shading normals
  glm::vec3 albedo{0.0f};          // diffuse albedo at the centroid (texture applied)
  glm::vec3 glossy{0.0f};          // the material's Phong lobe (scene/phong_lobe.h); 0: none
  float glossy_exponent = 0.0f;
  uint32_t element = kNoElement;   // this patch's index in ElementHierarchy::elements()
  uint32_t triangle = 0;           // index into Scene::triangles
  uint32_t surface = 0;            // see ElementHierarchy::surface_count()
  uint16_t subdivision_level = 0;  // times the source triangle was split 4-way
  // A sliver's piece that is a patch on its own: its code (triangle_bisection.h); 0 for every
  // other patch.
  uint32_t sliver_piece = 0;
  // The twin on the back of an open mesh's triangle (back_sides.h): same place, flipped
  // normal (corners in reverse order).
  // Emission is not a patch's: emitters reach receivers as direct light (DirectLight).
  bool back_side = false;
  // A merged patch (member_count > 0) is the triangles (or sliver pieces)
  // ElementHierarchy::members(*this): its area is theirs, its normals and albedo their
  // area-weighted means, its centre (Element::center) the point of the members nearest their
  // area-weighted centroid (the centroid itself on a planar group; on the surface, where a
  // curved group's centroid is not); `corners` and `triangle` are the member it lies on. Its
  // lobe is their material's.
  uint32_t first_member = 0;
  uint32_t member_count = 0;
};

struct HierarchyOptions {
  // Largest patch edge in metres; 0 picks default_max_edge(scene).
  float max_edge = 0.0f;
  // Refuse (Error OUT_OF_MEMORY, naming a patch size that fits) when the hierarchy would
  // have more elements than this; 0 leaves only the hard limit of 32-bit indices.
  uint64_t max_elements = 0;
  // When set, triangles of open meshes whose back faces open space get a twin patch for that
  // side (back_sides.h), decided with rays through this tracer of the same scene; when null
  // every surface is one-sided (the paper's solids).
  const RayTracer* back_sides = nullptr;
  // Glossy lobes with an exponent below this reflect as diffuse: their cosine-weighted
  // hemispherical albedo joins the patch's albedo and the lobe is dropped (see
  // fold_wide_glossy_lobes). 0 keeps every lobe.
  float glossy_fold_exponent = 0.0f;
};

// Default patch size: the scene's bounding-box diagonal / 16 (the comment below predates it). For the Cornell box (2 m room,
// diagonal 3.46 m: patches of at most 0.108 m) this gives 13,312 patches and 26,623 elements,
// whose three RGB bin tables (I_ex, L_in, I_total) take 123 MB at 128 bins and 184 MB at 192.
// extent / 64 would give four times that (106k elements, about 490 MB at 128 bins).
float default_max_edge(const Scene& scene);

// Times a triangle with longest edge `longest_edge` is split 4-way (each split halves every
// edge) so that its patches have edges <= max_edge. Capped at kMaxSubdivisionLevel.
inline constexpr int kMaxSubdivisionLevel = 20;
int subdivision_level(float longest_edge, float max_edge);

// Counts the build will produce for one scene, computed before allocating the hierarchy
// (saturate at UINT64_MAX): elements = 2 * patches - 1 (a binary tree with patches as
// leaves). Exact for a build without back sides when include_back_sides is false; with it,
// an upper bound that gives a twin to every patch with a triangle of an open mesh (the
// exposure test drops some). Grouping small triangles takes a sort, so counts are kept per
// max_edge: a budget search asks for the same sizes many times. Not thread-safe.
class PatchCount {
 public:
  explicit PatchCount(const Scene& scene);

  uint64_t patches(float max_edge, bool include_back_sides = true) const;
  uint64_t elements(float max_edge, bool include_back_sides = true) const;
  // Bytes the built hierarchy holds (elements, patches and member triangles, not the solver's
  // bin tables); the build briefly needs about as much again before the patches are ordered.
  uint64_t hierarchy_bytes(float max_edge, bool include_back_sides = true) const;
  // The smallest max_edge * 2^k (k >= 0) whose hierarchy has at most max_elements elements
  // (counting back sides as `elements` does): the coarsening to offer when a budget is
  // exceeded. Returns max_edge when it already fits.
  float max_edge_within_budget(float max_edge, uint64_t max_elements,
                               bool include_back_sides = true) const;

 private:
  struct Counts {
    uint64_t front = 0;       // patches without back sides
    uint64_t with_back = 0;   // upper bound with back sides
    uint64_t members = 0;     // member triangles of merged patches
  };
  const Counts& counts(float max_edge) const;

  const Scene& scene_;
  mutable std::vector<std::pair<float, Counts>> known_;
};

// One-off counts (a PatchCount for one question).
uint64_t estimate_patches(const Scene& scene, float max_edge, bool include_back_sides = true);
uint64_t estimate_elements(const Scene& scene, float max_edge, bool include_back_sides = true);
uint64_t estimate_hierarchy_bytes(const Scene& scene, float max_edge,
                                  bool include_back_sides = true);
float max_edge_within_budget(const Scene& scene, float max_edge, uint64_t max_elements);

class ElementHierarchy {
 public:
  ElementHierarchy() = default;
  // Throws Error(INVALID_ARGUMENT) for a max_edge that is not positive and finite, and
  // Error(OUT_OF_MEMORY) when the element count exceeds options.max_elements or 32 bits.
  ElementHierarchy(const Scene& scene, const HierarchyOptions& options = {});

  const std::vector<Element>& elements() const { return elements_; }
  // Patches in the order their elements appear (leaf order of the pre-order layout).
  const std::vector<Patch>& patches() const { return patches_; }
  const Element& root() const { return elements_.front(); }
  // The input triangles of a merged patch (empty for any other patch).
  std::span<const MemberTriangle> members(const Patch& patch) const {
    return std::span<const MemberTriangle>(members_).subspan(patch.first_member,
                                                              patch.member_count);
  }
  std::span<const MemberTriangle> members_all() const { return members_; }
  // Patches that are merged groups of small triangles, and the triangles in them.
  size_t merged_patch_count() const { return merged_patch_count_; }
  size_t member_count() const { return members_.size(); }

  size_t element_count() const { return elements_.size(); }
  size_t patch_count() const { return patches_.size(); }
  float max_edge() const { return max_edge_; }

  // Surfaces: the triangles of one mesh that share a material (and side). Bake points interpolate
  // only among patches of one surface; creases inside a surface (the faces of a box) are kept apart
  // by also weighting with normal agreement, which a mesh-wide id cannot break into seams on smooth
  // curved meshes the way a per-plane id would.
  uint32_t surface_count() const { return surface_count_; }
  // Patches that are back sides of open meshes' triangles (Patch::back_side).
  size_t back_side_count() const { return back_side_count_; }

  size_t memory_bytes() const;

 private:
  // The precomputation cache (precomputation_cache.cpp) writes and reads every member.
  friend struct PrecomputationCacheAccess;

  std::vector<Element> elements_;
  std::vector<Patch> patches_;
  std::vector<MemberTriangle> members_;
  size_t merged_patch_count_ = 0;
  uint32_t surface_count_ = 0;
  size_t back_side_count_ = 0;
  float max_edge_ = 0.0f;
};

}  // namespace bakegi::antiradiance
