// Light leaking through walls in the meshless method (Lehtinen et al. 2008, §5.2): the
// visibility-aware pull-push and Eq. 7 (visible_basis.h), the visibility-aware sender
// evaluation in the gathering integral (Eq. 16), and a closed two-room scene end to end.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "lights/direct_light.h"
#include "light_transport_fixtures.h"
#include "meshless_test_scenes.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/gather_integral.h"
#include "solvers/meshless/meshless_solver.h"
#include "solvers/meshless/multilevel_approximation.h"
#include "solvers/meshless/visible_basis.h"
#include "util/job_context.h"
#include "settings/settings.h"

namespace bakegi {
namespace {

using meshless::BasisHierarchy;
using meshless::BasisPoint;
using meshless::BasisValue;

using test::floor_point;
using test::floor_with_wall;

TEST(MeshlessVisibleBasis, PullAveragesOnlyVisibleChildrenAndEq7SkipsBlindLevels) {
  const Scene scene = floor_with_wall();
  const RayTracer tracer(scene);
  // Level 0: one point right of the wall whose support covers both sides. Level 1: one child
  // left of the wall (lit, 10) and two right of it (2 and 4).
  const BasisHierarchy basis({floor_point(0.5f, 2.0f, 0), floor_point(-0.5f, 1.0f, 1),
                              floor_point(0.3f, 1.0f, 1), floor_point(0.9f, 1.0f, 1)});
  ASSERT_EQ(basis.children(0).size(), 3u);
  const std::vector<float> samples = {0.0f, 10.0f, 2.0f, 4.0f};

  const meshless::VisibleRelations visible = meshless::visible_relations(basis, &tracer);
  const meshless::VisibleRelations plain = meshless::visible_relations(basis, nullptr);
  EXPECT_EQ(visible.pull_of(0).size(), 2u);
  EXPECT_EQ(plain.pull_of(0).size(), 3u);
  EXPECT_EQ(visible.coarser_of(1).size(), 0u);  // the left child sees no level-0 point
  EXPECT_EQ(visible.coarser_of(2).size(), 1u);
  EXPECT_EQ(visible.blocked, 2u);  // the left child's pull ray and its Eq. 7 ray

  const std::vector<float> alpha = meshless::visible_pull_push_project(basis, visible, samples, 1);
  // The coarse point's local mean is the kernel-weighted mean of the right children only.
  const BasisPoint& coarse = basis.point(0);
  const float w2 = meshless::weight(coarse, basis.point(2).position, basis.point(2).normal);
  const float w3 = meshless::weight(coarse, basis.point(3).position, basis.point(3).normal);
  const float mean = (w2 * 2.0f + w3 * 4.0f) / (w2 + w3);
  EXPECT_NEAR(alpha[0], mean, 1e-5f);
  EXPECT_GT(mean, 2.0f);
  EXPECT_LT(mean, 4.0f);
  // Eq. 7 without the blind coarse level: the left child keeps its sample; the right ones
  // carry their deviations from the single visible coarse function (B = 1 there).
  EXPECT_FLOAT_EQ(alpha[1], 10.0f);
  EXPECT_NEAR(alpha[2], 2.0f - mean, 1e-5f);
  EXPECT_NEAR(alpha[3], 4.0f - mean, 1e-5f);

  // Without a tracer the relations equal the plain P† (pull over all children).
  const std::vector<float> unblocked =
      meshless::visible_pull_push_project(basis, plain, samples, 1);
  const std::vector<float> reference = meshless::pull_push_project(basis, samples, 1);
  for (size_t j = 0; j < reference.size(); ++j) EXPECT_NEAR(unblocked[j], reference[j], 1e-5f);
  EXPECT_GT(unblocked[0], mean);  // the lit child pulled the coarse mean up
}

TEST(MeshlessVisibleBasis, GatherLeavesOutSendersBehindAWall) {
  const Scene scene = floor_with_wall();
  const RayTracer tracer(scene);
  // One sender centred left of the wall whose support covers the whole floor: a single
  // Shepard function is 1 wherever it reaches, so without visibility the receiver above the
  // right floor gathers from it.
  const BasisHierarchy senders({floor_point(-1.0f, 5.0f, 0)});
  meshless::GatherSettings settings;
  settings.rays = 256;
  std::vector<BasisValue> scratch;
  const glm::vec3 receiver(1.5f, 0.0f, 0.5f), down(0.0f, 0.0f, -1.0f);

  settings.visibility = false;
  meshless::SenderAccumulator plain(1);
  meshless::gather_links(scene, tracer, senders, receiver, down, 0, settings, plain, scratch);
  ASSERT_EQ(plain.touched().size(), 1u);
  EXPECT_GT(-plain.value(0)[1].z, 0.05f);  // ~ρ × (most of the lower hemisphere): ~0.4

  // With visibility every hit on the right floor is hidden from the sender point (the 1 m
  // wall is far taller than the lift of 0.15 × distance) and the wall's right face faces
  // away from the sender's normal: nothing at all.
  settings.visibility = true;
  meshless::SenderAccumulator visible(1);
  uint64_t visibility_rays = 0;
  meshless::gather_links(scene, tracer, senders, receiver, down, 0, settings, visible, scratch,
                         &visibility_rays);
  EXPECT_GT(visibility_rays, 0u);
  EXPECT_EQ(visible.touched().size(), 0u);
}

// Two closed 2 x 2 x 2 m rooms sharing the zero-thickness wall x = 0 (the harder case: floor
// points on both sides are closest there), a lamp in room A (x < 0).
SceneDescription two_rooms() {
  SceneDescription d;
  const uint32_t walls = test::add_material(d, glm::vec3(0.7f));
  d.meshes.push_back(
      test::make_cube(glm::vec3(-2, -1, 0), glm::vec3(0, 1, 2), test::Facing::kInward, walls));
  d.meshes.push_back(
      test::make_cube(glm::vec3(0, -1, 0), glm::vec3(2, 1, 2), test::Facing::kInward, walls));
  d.lights.push_back(test::point_light(glm::vec3(-1.0f, 0.0f, 1.5f), glm::vec3(10.0f)));
  return d;
}

// Floor and ceiling grids of both rooms; room A's are the first half.
BakePoints two_room_points() {
  std::vector<glm::vec3> positions, normals;
  for (float side : {-1.0f, 1.0f}) {
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 8; ++j) {
        const float x = side * (0.1f + 0.25f * i), y = -0.875f + 0.25f * j;
        positions.push_back(glm::vec3(x, y, 0.0f));
        normals.push_back(glm::vec3(0, 0, 1));
        positions.push_back(glm::vec3(x, y, 2.0f));
        normals.push_back(glm::vec3(0, 0, -1));
      }
    }
  }
  return test::make_points(positions, normals);
}

double room_b_over_room_a(const Scene& scene, const RayTracer& tracer, const BakePoints& points,
                          int64_t visibility) {
  const DirectLight direct(scene, tracer);
  Settings settings;
  settings.set("levels", int64_t(2));
  settings.set("gather_rays", int64_t(32));
  settings.set("visibility", visibility);
  MeshlessSolver solver;
  JobContext context;
  const auto field = solver.solve(SolveInputs{scene, tracer, direct, settings, &points}, context);
  std::vector<glm::vec3> values(points.size());
  field->evaluate(points, values, context);
  double a = 0.0, b = 0.0;
  const size_t half = points.size() / 2;
  for (size_t i = 0; i < points.size(); ++i) {
    (i < half ? a : b) += double(values[i].x + values[i].y + values[i].z);
  }
  return a > 0.0 ? b / a : 1.0;
}

TEST(MeshlessLeak, DarkRoomStaysDarkThroughAZeroThicknessWall) {
  const Scene scene = build_scene(two_rooms());
  const RayTracer tracer(scene);
  const BakePoints points = two_room_points();
  const double visible = room_b_over_room_a(scene, tracer, points, 1);
  const double plain = room_b_over_room_a(scene, tracer, points, 0);
  std::printf("meshless two rooms: room B / room A %.4f with visibility, %.4f without\n", visible,
              plain);
  // Room B's exact indirect light is 0. With visibility no basis relation crosses the wall
  // (measured: exactly 0); 2% is the target, far below the unblocked method's leak
  // (measured 0.125 here: coarse functions span the 2 m rooms), so the test tells them apart.
  EXPECT_LT(visible, 0.02);
  EXPECT_GT(plain, 0.02);
}

}  // namespace
}  // namespace bakegi
