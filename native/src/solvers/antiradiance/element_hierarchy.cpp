#include "solvers/antiradiance/element_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "scene/phong_lobe.h"
#include "solvers/antiradiance/back_sides.h"
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
  glm::vec3 position(glm::vec2 b) const {
    return (1.0f - b.x - b.y) * triangle_.p[0] + b.x * triangle_.p[1] + b.y * triangle_.p[2];
  }

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
    const glm::vec3 shading = (1.0f - centroid.x - centroid.y) * triangle_.n[0] +
                              centroid.x * triangle_.n[1] + centroid.y * triangle_.n[2];
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
  TreeBuilder(std::vector<PatchSeed>& seeds, std::vector<Element>& elements,
              std::vector<Patch>& patches)
      : seeds_(seeds), elements_(elements), patches_(patches) {}

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
      for (const glm::vec3& corner : patches_[elements_[e].patch].corners) {
        const glm::vec3 d = corner - cluster.center;
        radius2 = std::max(radius2, glm::dot(d, d));
      }
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
    for (const glm::vec3& corner : seed.patch.corners) {
      element.bounds_min = glm::min(element.bounds_min, corner);
      element.bounds_max = glm::max(element.bounds_max, corner);
      const glm::vec3 d = corner - seed.center;
      radius2 = std::max(radius2, glm::dot(d, d));
    }
    element.radius = std::sqrt(radius2);
    patches_.push_back(seed.patch);
    patches_.back().element = index;
  }

  std::vector<PatchSeed>& seeds_;
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

uint64_t estimate_patches(const Scene& scene, float max_edge, bool include_back_sides) {
  check_max_edge(max_edge);
  uint64_t patches = 0;
  for (const Triangle& t : scene.triangles) {
    const uint64_t sides = include_back_sides && on_open_mesh(scene, t) ? 2 : 1;
    patches = saturating_add(patches, sides << (2 * subdivision_level(longest_edge(t), max_edge)));
  }
  return patches;
}

uint64_t estimate_elements(const Scene& scene, float max_edge, bool include_back_sides) {
  const uint64_t patches = estimate_patches(scene, max_edge, include_back_sides);
  if (patches == 0) return 0;
  return patches > std::numeric_limits<uint64_t>::max() / 2 ? std::numeric_limits<uint64_t>::max()
                                                            : 2 * patches - 1;
}

uint64_t estimate_hierarchy_bytes(const Scene& scene, float max_edge, bool include_back_sides) {
  const uint64_t patches = estimate_patches(scene, max_edge, include_back_sides);
  const uint64_t per_patch = 2 * sizeof(Element) + sizeof(Patch);
  if (patches > std::numeric_limits<uint64_t>::max() / per_patch) {
    return std::numeric_limits<uint64_t>::max();
  }
  return patches == 0 ? 0 : patches * per_patch - sizeof(Element);  // 2 * patches - 1 elements
}

float max_edge_within_budget(const Scene& scene, float max_edge, uint64_t max_elements) {
  check_max_edge(max_edge);
  // Every doubling lowers each triangle's level by one until it reaches 0, so at most
  // kMaxSubdivisionLevel + 1 steps reach the coarsest hierarchy (one patch per triangle).
  for (int step = 0; step <= kMaxSubdivisionLevel + 1; ++step) {
    if (estimate_elements(scene, max_edge) <= max_elements) return max_edge;
    if (!std::isfinite(max_edge * 2.0f)) break;
    max_edge *= 2.0f;
  }
  return max_edge;
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

ElementHierarchy::ElementHierarchy(const Scene& scene, const HierarchyOptions& options) {
  max_edge_ = options.max_edge == 0.0f ? default_max_edge(scene) : options.max_edge;
  check_max_edge(max_edge_);
  if (scene.triangles.empty()) {
    throw Error(BAKEGI_ERROR_INVALID_SCENE, "antiradiance: the scene has no triangles");
  }

  // Which triangles get a back side decides the exact count, so it comes first (cheap: a few
  // rays per triangle of an open mesh).
  std::vector<uint8_t> back_side;
  if (options.back_sides != nullptr) back_side = exposed_back_sides(scene, *options.back_sides);
  uint64_t patch_count = 0;
  for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
    const uint64_t sides = !back_side.empty() && back_side[i] ? 2 : 1;
    patch_count = saturating_add(
        patch_count, sides << (2 * subdivision_level(longest_edge(scene.triangles[i]), max_edge_)));
  }
  const uint64_t elements = patch_count > std::numeric_limits<uint64_t>::max() / 2
                                ? std::numeric_limits<uint64_t>::max()
                                : 2 * patch_count - 1;
  const uint64_t budget = options.max_elements > 0
                              ? std::min(options.max_elements, kHardElementLimit)
                              : kHardElementLimit;
  if (elements > budget) {
    std::ostringstream message;
    message << "antiradiance: patches of at most " << max_edge_ << " m would make " << elements
            << " elements, more than the budget of " << budget << "; a patch size of "
            << max_edge_within_budget(scene, max_edge_, budget) << " m fits";
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, message.str());
  }

  // (mesh, material, side) -> id
  std::map<std::tuple<uint32_t, uint32_t, bool>, uint32_t> surfaces;
  std::vector<PatchSeed> seeds;
  seeds.reserve(size_t(patch_count));
  for (uint32_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    const auto [it, inserted] =
        surfaces.try_emplace({t.mesh, t.material, false}, uint32_t(surfaces.size()));
    const size_t first = seeds.size();
    TriangleSubdivider(scene, i, it->second, subdivision_level(longest_edge(t), max_edge_), seeds)
        .run();
    if (back_side.empty() || !back_side[i]) continue;
    const uint32_t back_surface =
        surfaces.try_emplace({t.mesh, t.material, true}, uint32_t(surfaces.size())).first->second;
    const size_t last = seeds.size();
    for (size_t s = first; s < last; ++s) {
      PatchSeed twin = seeds[s];  // the same center, bit for bit: link refinement pairs nothing
      std::swap(twin.patch.corners[1], twin.patch.corners[2]);
      twin.patch.normal = -twin.patch.normal;
      twin.patch.shading_normal = -twin.patch.shading_normal;
      twin.patch.surface = back_surface;
      twin.patch.back_side = true;
      seeds.push_back(twin);
    }
    back_side_count_ += last - first;
  }
  surface_count_ = uint32_t(surfaces.size());
  if (options.glossy_fold_exponent > 0.0f)
    fold_wide_glossy_lobes(seeds, options.glossy_fold_exponent);

  TreeBuilder(seeds, elements_, patches_).run();
}

size_t ElementHierarchy::memory_bytes() const {
  return elements_.capacity() * sizeof(Element) + patches_.capacity() * sizeof(Patch);
}

}  // namespace bakegi::antiradiance
