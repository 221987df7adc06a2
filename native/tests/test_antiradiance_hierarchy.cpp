// The Antiradiance element hierarchy (paper §3.2, §4.1): patches partition the input
// triangles below the size threshold, clusters are exact sums of their children, and the
// pre-order layout gives contiguous subtrees; the count is known before building.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "solvers/antiradiance/back_sides.h"
#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/link_refinement.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

using antiradiance::Element;
using antiradiance::ElementHierarchy;
using antiradiance::HierarchyOptions;
using antiradiance::kNoElement;
using antiradiance::Patch;

// Float positions are interpolated from barycentrics and areas are summed in float: a few
// ulps per operation, far below this relative tolerance.
constexpr float kRelativeTolerance = 1e-5f;

// A Cornell-box-like room: 2 m cube open at the front (y = -1), five walls of one quad
// each facing inwards, two boxes, a point light below the ceiling.
SceneDescription cornell_like() {
  SceneDescription d;
  const uint32_t white = add_material(d, {0.725f, 0.71f, 0.68f});
  const uint32_t red = add_material(d, {0.63f, 0.065f, 0.05f});
  const uint32_t green = add_material(d, {0.14f, 0.45f, 0.091f});
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  add_quad(d, {0, 0, 0}, x, y, 1, 1, white);  // floor, normal +z
  add_quad(d, {0, 0, 2}, y, x, 1, 1, white);  // ceiling, normal -z
  add_quad(d, {0, 1, 1}, z, x, 1, 1, white);  // back, normal -y
  add_quad(d, {-1, 0, 1}, y, z, 1, 1, red);   // left, normal +x
  add_quad(d, {1, 0, 1}, z, y, 1, 1, green);  // right, normal -x
  d.meshes.push_back(make_cube({0.03f, -0.67f, 0}, {0.63f, -0.07f, 0.6f}, Facing::kOutward, white));
  d.meshes.push_back(
      make_cube({-0.64f, -0.01f, 0}, {-0.04f, 0.59f, 1.2f}, Facing::kOutward, white));
  d.lights.push_back(point_light({0, 0, 1.9f}, glm::vec3(10.0f)));
  return d;
}

// One triangle (right angle at the origin, legs of length `leg` along x and y).
SceneDescription one_triangle(float leg) {
  SceneDescription d;
  const uint32_t material = add_material(d, {0.5f, 0.5f, 0.5f});
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {leg, 0, 0}, {0, leg, 0}};
  mesh.indices = {0, 1, 2};
  mesh.material = material;
  d.meshes.push_back(mesh);
  d.lights.push_back(point_light({0, 0, 1}, glm::vec3(1.0f)));
  return d;
}

double scene_area(const Scene& scene) {
  double area = 0.0;
  for (const Triangle& t : scene.triangles) area += t.area;
  return area;
}

float longest_edge(const Patch& p) {
  return std::max({glm::length(p.corners[1] - p.corners[0]),
                   glm::length(p.corners[2] - p.corners[1]),
                   glm::length(p.corners[0] - p.corners[2])});
}

// Everything the layout promises, checked element by element.
void expect_consistent_hierarchy(const Scene& scene, const ElementHierarchy& h) {
  const auto& elements = h.elements();
  const auto& patches = h.patches();
  ASSERT_FALSE(elements.empty());
  ASSERT_EQ(elements.size(), 2 * patches.size() - 1);

  // Root: covers the whole array and every patch corner.
  const Element& root = h.root();
  EXPECT_EQ(root.parent, kNoElement);
  EXPECT_EQ(root.level, 0);
  EXPECT_EQ(root.subtree_end, elements.size());
  // Back sides (twins of open meshes' patches) add their area once more.
  double area = scene_area(scene);
  for (const Patch& p : patches) area += p.back_side ? double(elements[p.element].area) : 0.0;
  EXPECT_NEAR(root.area, area, kRelativeTolerance * area);

  size_t patch_elements = 0;
  for (uint32_t i = 0; i < elements.size(); ++i) {
    const Element& e = elements[i];
    const float scale = std::max(1.0f, h.root().radius);
    // Subtree range contiguous and nested in the parent's.
    ASSERT_GT(e.subtree_end, i);
    ASSERT_LE(e.subtree_end, elements.size());
    if (i > 0) {
      ASSERT_NE(e.parent, kNoElement);
      ASSERT_LT(e.parent, i);  // pre-order: a push loop in array order sees parents first
      const Element& p = elements[e.parent];
      EXPECT_LE(e.subtree_end, p.subtree_end);
      EXPECT_EQ(e.level, p.level + 1);
    }
    if (e.is_patch) {
      ++patch_elements;
      EXPECT_EQ(e.subtree_end, i + 1);
      EXPECT_EQ(e.child_count, 0u);
      EXPECT_EQ(e.first_child, kNoElement);
      ASSERT_LT(e.patch, patches.size());
      EXPECT_EQ(patches[e.patch].element, i);
      continue;
    }

    // Children: first at i + 1, next sibling at the end of the previous subtree, the last
    // ending where the cluster ends; each names this cluster as its parent.
    ASSERT_EQ(e.child_count, 2u);
    EXPECT_EQ(e.first_child, i + 1);
    EXPECT_EQ(e.patch, kNoElement);
    uint32_t child = e.first_child;
    double child_area = 0.0;
    for (uint32_t k = 0; k < e.child_count; ++k) {
      ASSERT_LT(child, e.subtree_end);
      EXPECT_EQ(elements[child].parent, i);
      child_area += elements[child].area;
      child = elements[child].subtree_end;
    }
    EXPECT_EQ(child, e.subtree_end);
    EXPECT_NEAR(e.area, child_area, kRelativeTolerance * child_area);

    // Centre = area-weighted mean of the subtree's patch centroids; bounds and sphere hold
    // every patch corner of the subtree.
    glm::dvec3 weighted(0.0);
    double area = 0.0;
    for (uint32_t j = i + 1; j < e.subtree_end; ++j) {
      const Element& leaf = elements[j];
      if (!leaf.is_patch) continue;
      weighted += glm::dvec3(leaf.center) * double(leaf.area);
      area += leaf.area;
      for (const glm::vec3& c : patches[leaf.patch].corners) {
        EXPECT_LE(glm::length(c - e.center), e.radius * (1 + kRelativeTolerance));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(e.bounds_min, c)));
        EXPECT_TRUE(glm::all(glm::lessThanEqual(c, e.bounds_max)));
      }
    }
    const glm::vec3 expected_center(weighted / area);
    EXPECT_LE(glm::length(e.center - expected_center), kRelativeTolerance * scale)
        << "element " << i;
  }
  EXPECT_EQ(patch_elements, patches.size());
}

TEST(AntiradianceHierarchy, PatchesPartitionTheSceneBelowTheThreshold) {
  const Scene scene = build_scene(cornell_like());
  for (const float max_edge : {0.5f, 0.2f, antiradiance::default_max_edge(scene)}) {
    SCOPED_TRACE(max_edge);
    const ElementHierarchy h(scene, HierarchyOptions{max_edge, 0});
    EXPECT_EQ(h.max_edge(), max_edge);
    double area = 0.0;
    for (const Patch& p : h.patches()) {
      area += h.elements()[p.element].area;
      // Merged patches (groups of whole triangles) are checked in test_antiradiance_merging.
      if (p.member_count > 0) continue;
      EXPECT_LE(longest_edge(p), max_edge * (1 + kRelativeTolerance));
      // A patch is a quarter of its parent triangle per level: edges at least half the
      // threshold unless the source triangle was never split.
      if (p.subdivision_level > 0) EXPECT_GT(longest_edge(p), 0.5f * max_edge * 0.999f);
      // Normal and corners are the source triangle's plane.
      const Triangle& t = scene.triangles[p.triangle];
      EXPECT_EQ(p.normal, t.face_normal);
      for (const glm::vec3& c : p.corners) {
        EXPECT_NEAR(glm::dot(c - t.p[0], t.face_normal), 0.0f, 1e-5f);
      }
      const glm::vec3 winding =
          glm::cross(p.corners[1] - p.corners[0], p.corners[2] - p.corners[0]);
      EXPECT_GT(glm::dot(winding, t.face_normal), 0.0f);
      EXPECT_NEAR(0.5f * glm::length(winding), h.elements()[p.element].area,
                  1e-4f * h.elements()[p.element].area);
    }
    EXPECT_NEAR(area, scene_area(scene), 1e-6 * scene_area(scene));
    expect_consistent_hierarchy(scene, h);
  }
}

TEST(AntiradianceHierarchy, EstimateEqualsTheBuiltCount) {
  const Scene scene = build_scene(cornell_like());
  for (const float max_edge : {10.0f, 1.0f, 0.3f, 0.1f}) {
    SCOPED_TRACE(max_edge);
    // Without a tracer there are no back sides: the count without them is exact.
    const uint64_t estimate = antiradiance::estimate_elements(scene, max_edge, false);
    const ElementHierarchy h(scene, HierarchyOptions{max_edge, 0});
    EXPECT_EQ(estimate, h.element_count());
    EXPECT_EQ(antiradiance::estimate_patches(scene, max_edge, false), h.patch_count());
    EXPECT_EQ(antiradiance::estimate_hierarchy_bytes(scene, max_edge, false), h.memory_bytes());
    // The default counts a back side for every triangle of the five open wall quads.
    EXPECT_GT(antiradiance::estimate_patches(scene, max_edge), h.patch_count());
  }
  // At 20 m every triangle groups (longest edges up to 2.83 m, under 20 / 4) and cells of 10 m
  // hold the whole box: the two triangles of each planar quad are one patch (17 quads), and
  // each of the five open wall quads may get a back side.
  EXPECT_EQ(antiradiance::estimate_patches(scene, 20.0f, false), scene.triangles.size() / 2);
  EXPECT_EQ(antiradiance::estimate_patches(scene, 20.0f), scene.triangles.size() / 2 + 5);
}

// A right triangle with legs 1 (longest edge sqrt 2) and threshold 0.5 is split twice
// (sqrt 2 / 4 <= 0.5 < sqrt 2 / 2): 16 patches of area 1/32, 31 elements, 4 levels of
// clusters above the patches of a balanced tree.
TEST(AntiradianceHierarchy, OneTriangleSubdividesAnalytically) {
  const Scene scene = build_scene(one_triangle(1.0f));
  const ElementHierarchy h(scene, HierarchyOptions{0.5f, 0});
  ASSERT_EQ(h.patch_count(), 16u);
  ASSERT_EQ(h.element_count(), 31u);
  for (const Patch& p : h.patches()) {
    const Element& e = h.elements()[p.element];
    EXPECT_FLOAT_EQ(e.area, 1.0f / 32.0f);
    EXPECT_EQ(e.level, 4);
    EXPECT_EQ(p.subdivision_level, 2);
    EXPECT_NEAR(longest_edge(p), std::sqrt(2.0f) / 4.0f, 1e-6f);
  }
  EXPECT_FLOAT_EQ(h.root().area, 0.5f);
  // The area-weighted centre of the whole triangle is its centroid.
  EXPECT_NEAR(h.root().center.x, 1.0f / 3.0f, 1e-6f);
  EXPECT_NEAR(h.root().center.y, 1.0f / 3.0f, 1e-6f);
  // Bounding sphere about the centroid: the farthest corner is (1,0) or (0,1).
  EXPECT_NEAR(h.root().radius, std::sqrt(5.0f) / 3.0f, 1e-6f);
  expect_consistent_hierarchy(scene, h);
}

// Degenerate hierarchy: a triangle below the threshold is one patch that is also the root.
TEST(AntiradianceHierarchy, SingleTriangleBelowTheThresholdIsTheRoot) {
  const Scene scene = build_scene(one_triangle(0.1f));
  const ElementHierarchy h(scene);  // default threshold: the diagonal / 32 splits it
  EXPECT_GT(h.patch_count(), 1u);
  expect_consistent_hierarchy(scene, h);

  const ElementHierarchy single(scene, HierarchyOptions{1.0f, 0});
  ASSERT_EQ(single.element_count(), 1u);
  ASSERT_EQ(single.patch_count(), 1u);
  EXPECT_TRUE(single.root().is_patch);
  EXPECT_EQ(single.root().parent, kNoElement);
  EXPECT_EQ(single.root().subtree_end, 1u);
  EXPECT_FLOAT_EQ(single.root().area, 0.005f);
  expect_consistent_hierarchy(scene, single);
}

// A texture of 4 texels in a row whose red rises linearly with the texel index, mapped so
// that x in [0, 1] covers the texel centres u in [1/8, 7/8]: there bilinear lookup is
// linear, albedo red = 0.1 + 0.6 x and blue = 0.7 - 0.6 x at each patch centroid.
TEST(AntiradianceHierarchy, AlbedoPerPatch) {
  SceneDescription d;
  Texture texture;
  texture.width = 4;
  texture.height = 1;
  texture.set_texels(
      {{0.1f, 0.5f, 0.7f}, {0.3f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.3f}, {0.7f, 0.5f, 0.1f}});
  d.textures.push_back(texture);
  Material textured;
  textured.albedo = glm::vec3(1.0f);
  textured.albedo_texture = 0;
  d.materials.push_back(textured);
  const uint32_t red = add_material(d, {0.9f, 0.1f, 0.05f});
  const uint32_t lamp = add_material(d, {0.0f, 0.0f, 0.0f}, {3.0f, 2.0f, 1.0f});

  Mesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  auto uv = [](const glm::vec3& p) { return glm::vec2(0.125f + 0.75f * p.x, 0.5f); };
  for (const uint32_t i : quad.indices) quad.corner_uvs.push_back(uv(quad.positions[i]));
  quad.material = 0;
  d.meshes.push_back(quad);
  add_quad(d, {0.5f, 0.5f, 1.0f}, {0, 1, 0}, {1, 0, 0}, 0.5f, 0.5f, red);
  add_quad(d, {0.5f, 0.5f, 2.0f}, {0, 1, 0}, {1, 0, 0}, 0.1f, 0.1f, lamp);
  const Scene scene = build_scene(d);

  const ElementHierarchy h(scene, HierarchyOptions{0.1f, 0});
  size_t textured_patches = 0, red_patches = 0, lamp_patches = 0;
  for (const Patch& p : h.patches()) {
    const Element& e = h.elements()[p.element];
    const uint32_t mesh = scene.triangles[p.triangle].mesh;
    if (mesh == 0) {
      ++textured_patches;
      EXPECT_NEAR(p.albedo.x, 0.1f + 0.6f * e.center.x, 1e-5f);
      EXPECT_NEAR(p.albedo.y, 0.5f, 1e-5f);
      EXPECT_NEAR(p.albedo.z, 0.7f - 0.6f * e.center.x, 1e-5f);
    } else if (mesh == 1) {
      ++red_patches;
      EXPECT_EQ(p.albedo, glm::vec3(0.9f, 0.1f, 0.05f));
    } else {
      ++lamp_patches;
      EXPECT_EQ(p.albedo, glm::vec3(0.0f));  // an emitter reflects nothing
    }
    EXPECT_EQ(p.surface, mesh);  // one material per mesh here: surface = mesh
  }
  // Quads of 1 m (diagonal sqrt 2: 4 splits to 0.088 m) and 0.2 m (diagonal 0.28 m: 2).
  EXPECT_EQ(textured_patches, 2u * 256u);
  EXPECT_EQ(red_patches, 2u * 256u);
  EXPECT_EQ(lamp_patches, 2u * 16u);
  EXPECT_EQ(h.surface_count(), 3u);
}

// Surfaces are (mesh, material) pairs: one mesh with two materials gives two surfaces.
TEST(AntiradianceHierarchy, SurfacesSplitMeshesByMaterial) {
  SceneDescription d = cornell_like();
  const uint32_t blue = add_material(d, {0.1f, 0.1f, 0.8f});
  Mesh& box = d.meshes.back();
  box.triangle_materials.assign(box.indices.size() / 3, box.material);
  box.triangle_materials[0] = box.triangle_materials[1] = blue;
  const Scene scene = build_scene(d);
  const ElementHierarchy h(scene, HierarchyOptions{0.5f, 0});
  EXPECT_EQ(h.surface_count(), uint32_t(d.meshes.size() + 1));
  // The surface id is a function of (mesh, material) and distinguishes every pair.
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> pair_of_surface;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> surface_of_pair;
  for (const Patch& p : h.patches()) {
    const Triangle& t = scene.triangles[p.triangle];
    const std::pair<uint32_t, uint32_t> key{t.mesh, t.material};
    EXPECT_EQ(pair_of_surface.try_emplace(p.surface, key).first->second, key);
    EXPECT_EQ(surface_of_pair.try_emplace(key, p.surface).first->second, p.surface);
    EXPECT_LT(p.surface, h.surface_count());
  }
  EXPECT_EQ(pair_of_surface.size(), h.surface_count());
}

// With shading normals pointing away from a sphere's centre, the mean shading normal of a
// patch is the direction from the centre to the patch centroid (the interpolation is linear
// in the corners, as is the centroid); flat meshes keep the face normal.
TEST(AntiradianceHierarchy, MeanShadingNormals) {
  SceneDescription d;
  const uint32_t material = add_material(d, {0.5f, 0.5f, 0.5f});
  const glm::vec3 center(0.5f, -0.25f, 1.0f);
  Mesh sphere = make_icosphere(center, 0.8f, 1, material);
  for (const uint32_t i : sphere.indices) {
    sphere.corner_normals.push_back(glm::normalize(sphere.positions[i] - center));
  }
  d.meshes.push_back(sphere);
  add_quad(d, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, 2, 2, material);
  d.lights.push_back(point_light({0, 0, 3}, glm::vec3(1.0f)));
  const Scene scene = build_scene(d);
  const ElementHierarchy h(scene, HierarchyOptions{0.2f, 0});
  for (const Patch& p : h.patches()) {
    EXPECT_NEAR(glm::length(p.shading_normal), 1.0f, 1e-5f);
    if (scene.triangles[p.triangle].mesh == 0) {
      const glm::vec3 radial = glm::normalize(h.elements()[p.element].center - center);
      EXPECT_GT(glm::dot(p.shading_normal, radial), 1.0f - 1e-5f);
      EXPECT_GT(glm::dot(p.normal, radial), 0.9f);  // flat facets of a 80-face sphere
    } else {
      EXPECT_GT(glm::dot(p.shading_normal, p.normal), 1.0f - 1e-6f);
    }
  }
  expect_consistent_hierarchy(scene, h);
}

TEST(AntiradianceHierarchy, BudgetIsCheckedBeforeBuilding) {
  const Scene scene = build_scene(cornell_like());
  const float max_edge = 0.05f;
  const uint64_t needed = antiradiance::estimate_elements(scene, max_edge);
  const uint64_t budget = needed / 3;
  try {
    ElementHierarchy h(scene, HierarchyOptions{max_edge, budget});
    ADD_FAILURE() << "a hierarchy over budget was built";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY);
  }
  // The coarsening offered fits, and the next finer one (half of it) would not.
  const float coarser = antiradiance::max_edge_within_budget(scene, max_edge, budget);
  EXPECT_GT(coarser, max_edge);
  EXPECT_LE(antiradiance::estimate_elements(scene, coarser), budget);
  EXPECT_GT(antiradiance::estimate_elements(scene, 0.5f * coarser), budget);
  // The budget estimate is an upper bound (back sides for all open meshes' triangles); the
  // build without a tracer has none.
  EXPECT_EQ(ElementHierarchy(scene, HierarchyOptions{coarser, budget}).element_count(),
            antiradiance::estimate_elements(scene, coarser, false));
  EXPECT_EQ(antiradiance::max_edge_within_budget(scene, max_edge, needed), max_edge);

  for (const float bad :
       {-1.0f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    try {
      ElementHierarchy h(scene, HierarchyOptions{bad, 0});
      ADD_FAILURE() << "max_edge " << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_INVALID_ARGUMENT);
    }
  }
  // A threshold so fine that the count passes 32-bit indices is refused, not allocated.
  try {
    ElementHierarchy h(scene, HierarchyOptions{1e-6f, 0});
    ADD_FAILURE() << "a hierarchy beyond 32-bit indices was attempted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY);
  }
}

TEST(AntiradianceHierarchy, LayoutIsDeterministic) {
  const Scene scene = build_scene(cornell_like());
  const ElementHierarchy a(scene), b(scene);
  ASSERT_EQ(a.element_count(), b.element_count());
  for (size_t i = 0; i < a.element_count(); ++i) {
    EXPECT_EQ(a.elements()[i].center, b.elements()[i].center);
    EXPECT_EQ(a.elements()[i].subtree_end, b.elements()[i].subtree_end);
  }
}

// ---- Back sides of open meshes (back_sides.h) ----

// A closed inward room [-1, 1]² × [0, 2] divided at x = 0 by a one-sided plane facing -x
// (both halves are rooms); in the +x half an open box (no bottom face) stands on the floor.
SceneDescription divided_room() {
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.6f));
  d.meshes.push_back(make_cube({-1, -1, 0}, {1, 1, 2}, Facing::kInward, white));
  add_quad(d, {0, 0, 1}, {0, 0, 1}, {0, 1, 0}, 1, 1, white);  // normal (0,0,1)x(0,1,0) = -x
  Mesh box = make_cube({0.4f, -0.3f, 0}, {0.8f, 0.1f, 0.4f}, Facing::kOutward, white);
  box.indices.erase(box.indices.begin(), box.indices.begin() + 6);  // the bottom (z = lo) face
  d.meshes.push_back(box);
  d.lights.push_back(point_light({-0.5f, 0, 1.5f}, glm::vec3(5.0f)));
  return d;
}

TEST(AntiradianceBackSides, OnlyOpenSurfacesFacingOpenSpaceGetTwins) {
  const Scene scene = build_scene(divided_room());
  ASSERT_EQ(scene.mesh_topology.size(), 3u);
  EXPECT_FALSE(scene.mesh_topology[0].open());
  EXPECT_TRUE(scene.mesh_topology[1].open());
  EXPECT_TRUE(scene.mesh_topology[2].open());
  const RayTracer tracer(scene);
  const std::vector<uint8_t> exposed = antiradiance::exposed_back_sides(scene, tracer);
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    SCOPED_TRACE(i);
    const uint32_t mesh = scene.triangles[i].mesh;
    // The plane's back looks into the +x half (open); the closed room needs none; the box's
    // backs look into the cavity it closes with the floor, whose floor sees the box's inside.
    EXPECT_EQ(exposed[i], mesh == 1 ? 1 : 0);
  }
}

TEST(AntiradianceBackSides, TwinsMirrorTheirPatchesAndNeverLink) {
  const Scene scene = build_scene(divided_room());
  const RayTracer tracer(scene);
  const float max_edge = 0.3f;
  const ElementHierarchy one_sided(scene, HierarchyOptions{max_edge, 0});
  const ElementHierarchy h(scene, HierarchyOptions{max_edge, 0, &tracer});
  EXPECT_EQ(one_sided.back_side_count(), 0u);
  size_t plane_patches = 0;
  for (const Patch& p : one_sided.patches()) plane_patches += scene.triangles[p.triangle].mesh == 1;
  ASSERT_GT(plane_patches, 0u);
  EXPECT_EQ(h.back_side_count(), plane_patches);
  EXPECT_EQ(h.patch_count(), one_sided.patch_count() + plane_patches);
  // The upper-bound estimate also counts the open box's triangles.
  EXPECT_GT(antiradiance::estimate_patches(scene, max_edge), h.patch_count());
  expect_consistent_hierarchy(scene, h);

  // Each twin: the same center (bit for bit) and area as a front patch of its triangle, the
  // opposite normal, corners counter-clockwise around it, same albedo.
  std::map<std::pair<uint32_t, std::tuple<float, float, float>>, const Patch*> fronts;
  auto key = [&](const Patch& p) {
    const glm::vec3 c = h.elements()[p.element].center;
    return std::make_pair(p.triangle, std::make_tuple(c.x, c.y, c.z));
  };
  for (const Patch& p : h.patches()) {
    if (!p.back_side) fronts[key(p)] = &p;
  }
  size_t twins = 0;
  for (const Patch& p : h.patches()) {
    if (!p.back_side) continue;
    ++twins;
    const auto it = fronts.find(key(p));
    ASSERT_NE(it, fronts.end());
    const Patch& front = *it->second;
    EXPECT_EQ(p.normal, -front.normal);
    EXPECT_EQ(p.shading_normal, -front.shading_normal);
    EXPECT_EQ(p.albedo, front.albedo);
    EXPECT_NE(p.surface, front.surface);
    EXPECT_EQ(h.elements()[p.element].area, h.elements()[front.element].area);
    const glm::vec3 winding = glm::cross(p.corners[1] - p.corners[0], p.corners[2] - p.corners[0]);
    EXPECT_GT(glm::dot(winding, p.normal), 0.0f);
  }
  EXPECT_EQ(twins, plane_patches);

  // Link refinement pairs a twin with nothing in its own plane, its front patch included:
  // centers coincide, and every patch of the plane lies in the twin's plane (Fig. 7 culls).
  const auto bins = antiradiance::DirectionalBins::from_bin_count(48);
  const antiradiance::BinSpreading spreading(bins);
  const antiradiance::LinkSet links = antiradiance::build_links(h, bins, spreading);
  ASSERT_GT(links.links.size(), 0u);
  size_t plane_receptions = 0;
  for (const antiradiance::Link& link : links.links) {
    const Element& receiver = h.elements()[link.receiver];
    const Element& sender = h.elements()[link.sender];
    if (!receiver.is_patch || !sender.is_patch) continue;
    const Patch& r = h.patches()[receiver.patch];
    const Patch& s = h.patches()[sender.patch];
    if (scene.triangles[r.triangle].mesh != 1) continue;
    ++plane_receptions;
    EXPECT_FALSE(scene.triangles[s.triangle].mesh == 1)
        << "a patch of the plane receives from the plane itself";
    // A receiver on the plane only hears senders on its own side.
    EXPECT_GT(glm::dot(r.normal, sender.center - receiver.center), 0.0f);
  }
  EXPECT_GT(plane_receptions, 0u);
}

TEST(AntiradianceBackSides, EmptyOrLitWorldDecidesPlanesFacingNothing) {
  // A lone plane: its back faces only the world. Black: nothing can arrive, no twin; lit: the
  // sky arrives there and must be reflected and blocked, so a twin.
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.5f));
  add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1, white);
  d.lights.push_back(point_light({0, 0, 1}, glm::vec3(1.0f)));
  {
    const Scene scene = build_scene(d);
    const RayTracer tracer(scene);
    EXPECT_EQ(ElementHierarchy(scene, HierarchyOptions{0.5f, 0, &tracer}).back_side_count(), 0u);
  }
  d.world_radiance = glm::vec3(0.1f);
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  const ElementHierarchy h(scene, HierarchyOptions{0.5f, 0, &tracer});
  EXPECT_EQ(h.back_side_count() * 2, h.patch_count());
}

}  // namespace
}  // namespace bakegi::test
