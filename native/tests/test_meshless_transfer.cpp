// The meshless transfer (Lehtinen et al. 2008, §3): the gathering integral of Eq. 16 against
// a closed-form form factor, and the solver end to end (relighting equals a full solve).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/gather_integral.h"
#include "solvers/meshless/meshless_solver.h"
#include "util/error.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

using meshless::BasisHierarchy;
using meshless::BasisPoint;
using meshless::BasisValue;
using meshless::GatherSettings;
using meshless::SenderAccumulator;

// Form factor from a differential area to a parallel rectangle [0, a] x [0, b] at height h,
// one corner straight above it (Howell's catalogue, C-11).
double corner_form_factor(double a, double b, double h) {
  const double x = a / h, y = b / h;
  const double sx = std::sqrt(1.0 + x * x), sy = std::sqrt(1.0 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * M_PI);
}

TEST(MeshlessGather, UniformSenderOverAParallelPlateGivesAlbedoTimesFormFactor) {
  // One sender function whose support covers the whole plate is 1 on it (Shepard with a
  // single point), so Eq. 16 reduces to (ρ/π) ∫_plate ω̄ dω: its normal component is ρ F
  // (F the form factor), its tangential components vanish when the receiver sits below the
  // plate's centre.
  const float albedo = 0.6f, half = 1.0f, height = 0.5f;
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(albedo));
  // Faces down (u x v = -z) towards the receiver at the origin.
  test::add_quad(d, glm::vec3(0.0f, 0.0f, height), glm::vec3(0, 1, 0), glm::vec3(1, 0, 0), half,
                 half, grey);
  d.lights.push_back(test::point_light(glm::vec3(0.0f, 0.0f, 0.2f), glm::vec3(1.0f)));  // lamps
  // are not geometry: a scene must have a light, and this one neither blocks nor reflects.
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  BasisPoint sender;
  sender.position = glm::vec3(0.0f, 0.0f, height);
  sender.normal = glm::vec3(0.0f, 0.0f, -1.0f);
  sender.radius = 10.0f;
  const BasisHierarchy senders({sender});

  GatherSettings settings;
  settings.rays = 64 * 64;
  SenderAccumulator accumulator(1);
  std::vector<BasisValue> scratch;
  const uint64_t rays =
      meshless::gather_links(scene, tracer, senders, glm::vec3(0.0f), glm::vec3(0, 0, 1), 0,
                             settings, accumulator, scratch);
  EXPECT_EQ(rays, settings.rays);
  ASSERT_EQ(accumulator.touched().size(), 1u);
  const double expected = albedo * 4.0 * corner_form_factor(half, half, height);
  const meshless::LinkValue& link = accumulator.value(0);
  for (int c = 0; c < 3; ++c) {
    // 4096 jittered uniform-hemisphere rays: the plate's outline crosses about 2·64 strata,
    // each off by at most its own weight 2π/4096 (times ρ/π, times cos <= 1), so the
    // estimate is within 128 · 2 · 0.6 / 4096 = 3.8% of ρ F at worst and far closer in
    // practice (the errors along the outline cancel); 1% still fails any wrong factor of π,
    // 2 or a cosine.
    EXPECT_NEAR(link[c].z, expected, 0.01 * expected) << "channel " << c;
    EXPECT_NEAR(link[c].x, 0.0, 0.01 * expected);
    EXPECT_NEAR(link[c].y, 0.0, 0.01 * expected);
  }
}

// A closed room with a block and a point light, and bake points on its floor.
SceneDescription room_with_block(glm::vec3 light) {
  SceneDescription d;
  const uint32_t walls = test::add_material(d, glm::vec3(0.6f, 0.5f, 0.4f));
  const uint32_t block = test::add_material(d, glm::vec3(0.3f, 0.6f, 0.3f));
  d.meshes.push_back(
      test::make_cube(glm::vec3(-1, -1, 0), glm::vec3(1, 1, 2), test::Facing::kInward, walls));
  d.meshes.push_back(test::make_cube(glm::vec3(-0.3f, -0.3f, 0.0f), glm::vec3(0.3f, 0.3f, 0.8f),
                                     test::Facing::kOutward, block));
  d.lights.push_back(test::point_light(light, glm::vec3(10.0f)));
  return d;
}

BakePoints floor_points() {
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) {
      positions.push_back(glm::vec3(-0.9f + 0.16f * i, -0.9f + 0.16f * j, 0.0f));
      normals.push_back(glm::vec3(0, 0, 1));
    }
  }
  return test::make_points(positions, normals);
}

Settings small_meshless_settings() {
  Settings settings;
  settings.set("levels", int64_t(3));
  settings.set("gather_rays", int64_t(64));
  return settings;
}

TEST(MeshlessSolver, RelightEqualsAFullSolveWithTheMovedLight) {
  const BakePoints points = floor_points();
  const Settings settings = small_meshless_settings();
  const Scene first = build_scene(room_with_block(glm::vec3(0.5f, 0.2f, 1.8f)));
  const Scene moved = build_scene(room_with_block(glm::vec3(-0.6f, -0.4f, 1.5f)));
  const RayTracer tracer(first);  // same geometry: one BVH serves both

  MeshlessSolver solver;
  JobContext context;
  const DirectLight direct_first(first, tracer);
  ASSERT_NO_THROW(
      solver.solve(SolveInputs{first, tracer, direct_first, settings, &points}, context));
  const auto precomputation = solver.precomputation();
  ASSERT_NE(precomputation, nullptr);
  EXPECT_GT(precomputation->memory_bytes(), 0u);

  const DirectLight direct_moved(moved, tracer);
  MeshlessSolver relighter;
  JobContext relight_context;
  const auto relit = relighter.relight(SolveInputs{moved, tracer, direct_moved, settings, &points},
                                       *precomputation, relight_context);
  std::vector<glm::vec3> relit_values(points.size());
  relit->evaluate(points, relit_values, relight_context);

  MeshlessSolver full;
  JobContext full_context;
  const auto direct_field =
      full.solve(SolveInputs{moved, tracer, direct_moved, settings, &points}, full_context);
  std::vector<glm::vec3> full_values(points.size());
  direct_field->evaluate(points, full_values, full_context);

  // Placement and links depend on geometry, materials and settings only, so relighting must
  // reproduce the full solve exactly.
  double total = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(relit_values[i], full_values[i]) << "point " << i;
    total += relit_values[i].x;
  }
  EXPECT_GT(total, 0.0);  // the floor does receive indirect light
}

TEST(MeshlessSolver, BadSettingsAndMissingPointsAreRefused) {
  const Scene scene = build_scene(room_with_block(glm::vec3(0.0f, 0.0f, 1.5f)));
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  MeshlessSolver solver;
  JobContext context;
  Settings bad_viewpoint = small_meshless_settings();
  bad_viewpoint.set("viewpoint", std::string("1,2"));
  const BakePoints points = floor_points();
  EXPECT_THROW(solver.solve(SolveInputs{scene, tracer, direct, bad_viewpoint, &points}, context),
               Error);
  // Without bake points the basis needs a viewpoint to place its points from.
  EXPECT_THROW(solver.solve(SolveInputs{scene, tracer, direct, small_meshless_settings()}, context),
               Error);
  Settings with_viewpoint = small_meshless_settings();
  with_viewpoint.set("viewpoint", std::string("0.5,0.5,1.5"));
  EXPECT_NO_THROW(solver.solve(SolveInputs{scene, tracer, direct, with_viewpoint}, context));
}

}  // namespace
}  // namespace bakegi
