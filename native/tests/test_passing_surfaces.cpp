// See-through surfaces (scene/passing_surfaces.h): rays pass a triangle with its material's
// probability, 1 - opacity x texture x (1 - transmission); a ray that passes goes on as if
// the triangle were not there, in closest-hit and shadow rays alike. Checked as counts of
// passing rays (binomial: tolerances are 5 standard deviations), as a lamp's shadow through a
// pane and as the indirect light a path tracer carries through one.
#include <gtest/gtest.h>

#include <cmath>

#include "light_transport_fixtures.h"
#include "lights/direct_light.h"
#include "scene/fresnel.h"
#include "util/random.h"

namespace bakegi {
namespace {

// A floor [-2, 2]^2 at z = 0 (triangles 0 and 1) under a pane [-1, 1]^2 at z = 1 (triangles 2
// and 3) whose material's pass fields are set by `pane`.
template <typename SetPane>
SceneDescription floor_under_pane(SetPane&& pane) {
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  const uint32_t glass = test::add_material(d, glm::vec3(0.0f));
  const glm::vec3 x(1, 0, 0), y(0, 1, 0);
  test::add_quad(d, {0, 0, 0}, x, y, 2, 2, grey);
  test::add_quad_with_uvs(d, {0, 0, 1}, x, y, 1, 1, glass, {0, 0}, {1, 1});
  pane(d, d.materials[glass]);
  d.lights.push_back(test::point_light({0, 0, 3}, glm::vec3(1.0f)));
  return d;
}

struct Counts {
  int pane = 0, floor = 0, other = 0, blocked = 0;
};

// n rays straight down from z = 2 at (x, y) in [x0, x1] x [-0.9, 0.9], each its own seed.
Counts cast_down(const RayTracer& tracer, int n, float x0, float x1) {
  Counts c;
  Pcg32 rng(7, 1);
  for (int k = 0; k < n; ++k) {
    const float px = x0 + (x1 - x0) * rng.next_float(), py = -0.9f + 1.8f * rng.next_float();
    Ray ray{{px, py, 2.0f}, {0, 0, -1}, 0.0f, 1e30f, uint32_t(k)};
    const Hit hit = tracer.intersect(ray);
    if (hit.hit && (hit.triangle == 2 || hit.triangle == 3) && std::abs(hit.t - 1.0f) < 1e-4f) {
      ++c.pane;
    } else if (hit.hit && hit.triangle < 2 && std::abs(hit.t - 2.0f) < 1e-4f) {
      ++c.floor;
    } else {
      ++c.other;
    }
    ray.tfar = 1.5f;  // ends between pane and floor: only the pane can block it
    if (tracer.occluded(ray)) ++c.blocked;
  }
  return c;
}

void expect_share(int count, int n, double p, const char* what) {
  const double sigma = std::sqrt(p * (1.0 - p) / n);
  EXPECT_NEAR(double(count) / n, p, 5.0 * sigma + 1e-9) << what;
}

TEST(PassingSurfaces, RaysPassWithTheMaterialsProbability) {
  const int n = 20000;
  const struct {
    float opacity, transmission, pass;
  } cases[] = {{0.3f, 0.0f, 0.7f}, {1.0f, 0.8f, 0.8f}, {0.5f, 0.5f, 0.75f}, {0.0f, 0.0f, 1.0f}};
  for (const auto& c : cases) {
    const Scene scene = build_scene(floor_under_pane([&](SceneDescription&, Material& m) {
      m.opacity = c.opacity;
      m.transmission = c.transmission;
    }));
    const RayTracer tracer(scene);
    ASSERT_TRUE(tracer.has_passing_surfaces());
    const Counts counts = cast_down(tracer, n, -0.9f, 0.9f);
    EXPECT_EQ(counts.other, 0);
    EXPECT_EQ(counts.pane + counts.floor, n);
    expect_share(counts.floor, n, c.pass, "closest hits that passed the pane");
    expect_share(n - counts.blocked, n, c.pass, "shadow rays that passed the pane");
  }
}

TEST(PassingSurfaces, GlassPassesLessAtGrazingAnglesAsFresnelSays) {
  // Glass of index 1.5 passing its cosine-weighted average 1 - F_avg = 0.9082: at angle theta
  // it passes (1 - F(theta)) / (1 - F_avg) of that, 0.96 at normal incidence, 0.70 at 75
  // degrees; shadow rays through the pane's middle from 0.5 m away.
  const float average = fresnel_hemispherical_average(1.5f);
  EXPECT_NEAR(average, 0.0918f, 5e-4f);
  EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);
  const Scene scene = build_scene(floor_under_pane([&](SceneDescription&, Material& m) {
    m.transmission = 1.0f - average;
    m.transmission_ior = 1.5f;
  }));
  const RayTracer tracer(scene);
  const int n = 20000;
  for (const float degrees : {0.0f, 45.0f, 75.0f}) {
    const float theta = degrees * 3.14159265f / 180.0f;
    const glm::vec3 toward(-std::sin(theta), 0.0f, -std::cos(theta));
    Pcg32 rng(11, 3);
    int passed = 0;
    for (int k = 0; k < n; ++k) {
      const glm::vec3 at(-0.5f + rng.next_float(), -0.5f + rng.next_float(), 1.0f);
      const Ray ray{at - 0.5f * toward, toward, 0.0f, 0.6f, uint32_t(k)};
      passed += tracer.occluded(ray) ? 0 : 1;
    }
    const double expected = 1.0 - fresnel_dielectric(std::cos(theta), 1.5f);
    expect_share(passed, n, expected, "share passed at this angle");
  }
}

TEST(PassingSurfaces, AnOpaqueSceneTracesAsBefore) {
  const Scene scene = build_scene(floor_under_pane([](SceneDescription&, Material&) {}));
  const RayTracer tracer(scene);
  EXPECT_FALSE(tracer.has_passing_surfaces());
  const Counts counts = cast_down(tracer, 1000, -0.9f, 0.9f);
  EXPECT_EQ(counts.pane, 1000);
  EXPECT_EQ(counts.blocked, 1000);
}

TEST(PassingSurfaces, AnOpacityTextureCutsHoles) {
  // Red channel 0, 0, 1, 1 along u: the pane's -x half (u < 0.5) is a hole, its +x half solid
  // (bilinear: u = 0.25 reads texels 0 and 1, u = 0.75 texels 2 and 3).
  const Scene scene = build_scene(floor_under_pane([](SceneDescription& d, Material& m) {
    m.opacity_texture = test::add_texture(
        d, 4, 1, [](uint32_t i, uint32_t) { return glm::vec3(i < 2 ? 0.0f : 1.0f, 0.5f, 0.5f); });
  }));
  const RayTracer tracer(scene);
  const Counts hole = cast_down(tracer, 2000, -0.55f, -0.45f);  // u in [0.225, 0.275]
  const Counts solid = cast_down(tracer, 2000, 0.45f, 0.55f);   // u in [0.725, 0.775]
  EXPECT_EQ(hole.floor, 2000);
  EXPECT_EQ(hole.blocked, 0);
  EXPECT_EQ(solid.pane, 2000);
  EXPECT_EQ(solid.blocked, 2000);
}

TEST(PassingSurfaces, OneRayGetsOneAnswerAndSeedsTellRaysApart) {
  const Scene scene =
      build_scene(floor_under_pane([](SceneDescription&, Material& m) { m.opacity = 0.5f; }));
  const RayTracer tracer(scene);
  int passed = 0;
  for (uint32_t seed = 0; seed < 200; ++seed) {
    const Ray ray{{0.1f, 0.2f, 2.0f}, {0, 0, -1}, 0.0f, 1.5f, seed};
    const bool blocked = tracer.occluded(ray);
    EXPECT_EQ(tracer.occluded(ray), blocked) << "the same ray must get the same answer";
    EXPECT_EQ(tracer.intersect(ray).hit, blocked) << "closest hit and shadow ray agree";
    passed += blocked ? 0 : 1;
  }
  expect_share(passed, 200, 0.5, "one origin and direction, 200 seeds");
}

TEST(PassingSurfaces, ALampShinesThroughAPaneByItsTransmission) {
  // The point lamp at (0, 0, 3) above the floor, the pane in between: the lamp's
  // light-sampled irradiance at (0.1, 0.3, 0) is 0.6 of the unshadowed 3 / 9.1^1.5 behind a
  // pane passing 60%. Every shadow ray has the same origin and direction; only the sample's
  // own numbers (the seed) tell them apart. (Not at the floor's centre: a ray through the
  // pane's diagonal meets both its triangles and is decided twice.)
  const Scene scene =
      build_scene(floor_under_pane([](SceneDescription&, Material& m) { m.transmission = 0.6f; }));
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  const SurfacePoint x{{0.1f, 0.3f, 0}, {0, 0, 1}, {0, 0, 1}};
  const int n = 8192;
  double sum = 0.0;
  uint64_t rays = 0;
  for (int k = 0; k < n; ++k) {
    RandomStream rng = sample_stream(5, 0, uint64_t(k));
    sum += direct.lamp_irradiance(x, rng, rays).x;
  }
  const double share = sum / n / (3.0 / std::pow(9.1, 1.5));
  EXPECT_NEAR(share, 0.6, 5.0 * std::sqrt(0.6 * 0.4 / n));
}

TEST(PassingSurfaces, ThePathTracerCarriesIndirectLightThroughAPane) {
  // A lamp at (0, 0, 0.5) over the grey floor, a black pane at z = 1 reaching far beyond the
  // floor, receivers at z = 2 facing down: their indirect light is the floor's reflection,
  // which crosses the pane once, so a pane passing 40% leaves 0.4 of it (a black pane reflects
  // nothing where rays stop at it).
  auto scene_with = [](float transmission) {
    SceneDescription d;
    const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
    const uint32_t glass = test::add_material(d, glm::vec3(0.0f));
    d.materials[glass].transmission = transmission;
    const glm::vec3 x(1, 0, 0), y(0, 1, 0);
    test::add_quad(d, {0, 0, 0}, x, y, 2, 2, grey);
    test::add_quad(d, {0, 0, 1}, x, y, 50, 50, glass);
    d.lights.push_back(test::point_light({0, 0, 0.5f}, glm::vec3(10.0f)));
    return d;
  };
  std::vector<glm::vec3> positions;
  for (int i = 0; i < 8; ++i) positions.push_back({-0.7f + 0.2f * i, 0.1f, 2.0f});
  const BakePoints points =
      test::make_points(positions, std::vector<glm::vec3>(positions.size(), {0, 0, -1}));
  test::BakeOptions options;
  options.samples = 4096;
  double clear = 0.0, behind = 0.0;
  for (const glm::vec3& v : test::Baker(scene_with(1.0f)).bake(points, options)) clear += v.x;
  for (const glm::vec3& v : test::Baker(scene_with(0.4f)).bake(points, options)) behind += v.x;
  ASSERT_GT(clear, 0.0);
  // The floor seen from 1 m away through the pane: each point's estimate has a relative
  // spread of about 1.5 per path; 8 x 4096 paths put the ratio's spread near 1.5%.
  EXPECT_NEAR(behind / clear, 0.4, 0.04);
}

}  // namespace
}  // namespace bakegi
