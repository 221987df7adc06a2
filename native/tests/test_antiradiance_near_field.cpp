// The near-field output of antiradiance: which patch a ray hit lands on (patch_locator.h),
// and what the final gather does next to another surface (near_field_gather.h).
#include <gtest/gtest.h>

#include <vector>

#include "light_transport_fixtures.h"
#include "scene/scene_validation.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/patch_locator.h"
#include "util/random.h"

namespace bakegi {
namespace {

using antiradiance::ElementHierarchy;
using antiradiance::HierarchyOptions;
using antiradiance::Patch;
using antiradiance::PatchLocator;

// Barycentric containment of p in the patch's triangle (p in its plane), with slack for
// points on shared edges.
bool contains(const Patch& patch, const glm::vec3& p) {
  const glm::vec3 a = patch.corners[0], b = patch.corners[1], c = patch.corners[2];
  const glm::vec3 n = glm::cross(b - a, c - a);
  const float area2 = glm::dot(n, n);
  const float u = glm::dot(glm::cross(c - b, p - b), n) / area2;
  const float v = glm::dot(glm::cross(a - c, p - c), n) / area2;
  const float w = 1.0f - u - v;
  constexpr float kSlack = 1e-4f;
  return u >= -kSlack && v >= -kSlack && w >= -kSlack;
}

TEST(AntiradiancePatchLocator, FindsThePatchThatContainsEveryPointOfATriangle) {
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  // A room (faces split 0-3 times by size) with a block whose faces are split differently; at
  // 5 m every face's two triangles are one merged patch.
  d.meshes.push_back(
      test::make_cube(glm::vec3(-2, -1, 0), glm::vec3(2, 1, 1.5f), test::Facing::kInward, grey));
  d.meshes.push_back(test::make_cube(glm::vec3(-0.2f, -0.2f, 0.0f), glm::vec3(0.2f, 0.2f, 0.3f),
                                     test::Facing::kOutward, grey));
  d.lights.push_back(test::point_light(glm::vec3(0, 0, 1), glm::vec3(1.0f)));
  const Scene scene = build_scene(d);
  for (float max_edge : {5.0f, 0.7f, 0.25f}) {
    const ElementHierarchy hierarchy(scene, HierarchyOptions{max_edge, 0});
    const PatchLocator locator(scene, hierarchy);
    Pcg32 rng(7, 3);
    for (uint32_t t = 0; t < scene.triangles.size(); ++t) {
      const Triangle& triangle = scene.triangles[t];
      for (int s = 0; s < 200; ++s) {
        float b1 = rng.next_float(), b2 = rng.next_float();
        if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
        const glm::vec3 p =
            triangle.p[0] * (1.0f - b1 - b2) + triangle.p[1] * b1 + triangle.p[2] * b2;
        const uint32_t found = locator.find(t, b1, b2, false);
        ASSERT_NE(found, PatchLocator::kNone) << "triangle " << t;
        const Patch& patch = hierarchy.patches()[found];
        EXPECT_FALSE(patch.back_side);
        if (patch.member_count > 0) {
          // A merged patch holds whole triangles: t must be one of them.
          bool member = false;
          for (const auto& m : hierarchy.members(patch)) member = member || m.triangle == t;
          EXPECT_TRUE(member) << "triangle " << t << ", max edge " << max_edge;
          continue;
        }
        EXPECT_EQ(patch.triangle, t);
        EXPECT_TRUE(contains(patch, p))
            << "triangle " << t << " at (" << b1 << ", " << b2 << "), max edge " << max_edge;
      }
      // Closed solids have no back-side patches: the inside reflects nothing.
      EXPECT_EQ(locator.find(t, 0.3f, 0.3f, true), PatchLocator::kNone);
    }
  }
}

}  // namespace
}  // namespace bakegi
