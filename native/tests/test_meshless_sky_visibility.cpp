// The senders' sky visibility (sky_visibility.h) against the view factor of a differential
// area to a parallel square opening centred above it, and the two exact cases (open sky,
// closed box).
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "solvers/meshless/sky_visibility.h"
#include "util/job_context.h"

namespace bakegi {
namespace {

using meshless::BasisHierarchy;
using meshless::BasisPoint;

// `count` points facing up on a 1 mm disc around the origin (distinct, so each draws its
// own rays).
BasisHierarchy points_at_origin(int count) {
  std::vector<BasisPoint> points;
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / count;
    BasisPoint p;
    p.position = glm::vec3(1e-3 * std::cos(angle), 1e-3 * std::sin(angle), 0.0);
    p.normal = glm::vec3(0, 0, 1);
    p.radius = 0.1f;
    points.push_back(p);
  }
  return BasisHierarchy(points);
}

double mean_visibility(SceneDescription d, const BasisHierarchy& points) {
  d.world_radiance = glm::vec3(1.0f);  // a scene needs a light; V does not depend on it
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  JobContext context;
  uint64_t rays = 0;
  const std::vector<float> v =
      meshless::sky_visibility(points, tracer, meshless::SkyVisibilitySettings{}, context, rays);
  EXPECT_EQ(rays, uint64_t(points.size()) * 64);
  double sum = 0.0;
  for (float x : v) sum += x;
  return sum / double(v.size());
}

TEST(MeshlessSkyVisibility, MatchesTheViewFactorOfASquareOpening) {
  // A ceiling at height h of four large quads around a square hole of half-size a: from the
  // origin the hole's view factor is (4/π) X atan(X), X = A/√(1+A²), A = a/h (the corner
  // formula for a parallel rectangle, four times). The ceiling's 1 km extent leaves a band
  // near the horizon of view factor ~(h/1000)² open: negligible.
  const float a = 0.3f, h = 0.5f, far = 1000.0f;
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  const glm::vec3 x(1, 0, 0), y(0, 1, 0);
  const float strip = 0.5f * (far - a), middle = 0.5f * (far + a);
  test::add_quad(d, {0, -middle, h}, y, x, strip, far, grey);
  test::add_quad(d, {0, middle, h}, y, x, strip, far, grey);
  test::add_quad(d, {-middle, 0, h}, y, x, a, strip, grey);
  test::add_quad(d, {middle, 0, h}, y, x, a, strip, grey);
  test::add_quad(d, {0, 0, -0.01f}, x, y, 2.0f, 2.0f, grey);  // a floor below, never seen
  const double A = a / h, X = A / std::sqrt(1.0 + A * A);
  const double expected = 4.0 / std::numbers::pi * X * std::atan(X);  // 0.311
  // 256 points x 64 stratified rays: binomial spread of the mean at most 0.3% absolute
  // (1% relative); 4% allows the strata's correlation and the disc's 1 mm.
  const double got = mean_visibility(d, points_at_origin(256));
  EXPECT_NEAR(got / expected, 1.0, 0.04) << "got " << got << ", expected " << expected;
}

TEST(MeshlessSkyVisibility, IsOneUnderOpenSkyAndZeroInAClosedBox) {
  SceneDescription open;
  const uint32_t grey = test::add_material(open, glm::vec3(0.5f));
  test::add_quad(open, {0, 0, -0.01f}, {1, 0, 0}, {0, 1, 0}, 2.0f, 2.0f, grey);
  EXPECT_EQ(mean_visibility(open, points_at_origin(16)), 1.0);

  SceneDescription closed;
  const uint32_t white = test::add_material(closed, glm::vec3(0.5f));
  closed.meshes.push_back(test::make_cube(glm::vec3(-1, -1, -0.5f), glm::vec3(1, 1, 1.5f),
                                          test::Facing::kInward, white));
  EXPECT_EQ(mean_visibility(closed, points_at_origin(16)), 0.0);
}

}  // namespace
}  // namespace bakegi
