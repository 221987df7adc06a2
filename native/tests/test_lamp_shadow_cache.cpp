// The lamps' blocked places (lights/lamp_shadow_cache.h): a closed room lit by a sun through a
// hole of 2 cm, on a grid so coarse that the pilot misses the hole's sun spot. The spot's cell
// is then judged blocked, and its light samples are kept 1 in 8 and weighed 8x: the spot's
// light stays what it is (unbiased), the dark floor's shadow rays fall to an eighth, and
// nothing changes where the pilot saw the sun.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "light_transport_fixtures.h"
#include "lights/direct_light.h"
#include "lights/lamp_shadow_cache.h"
#include "util/random.h"

namespace bakegi {
namespace {

// The room [-2, 2] x [-2, 2] x [0, 3]; its +x wall has a 2 x 2 cm hole at (2, 0, 1.5); the sun
// shines through it 45 degrees down, onto the floor around (0.5, 0, 0).
SceneDescription room_with_a_hole() {
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  const glm::vec3 y(0, 1, 0), z(0, 0, 1);
  test::add_room_without_plus_x_wall(d, grey);
  test::add_quad(d, {2, 0, 0.745f}, z, y, 0.745f, 2, grey);  // +x wall, under the hole
  test::add_quad(d, {2, 0, 2.255f}, z, y, 0.745f, 2, grey);  // over it
  test::add_quad(d, {2, -1.005f, 1.5f}, z, y, 0.01f, 0.995f, grey);
  test::add_quad(d, {2, 1.005f, 1.5f}, z, y, 0.01f, 0.995f, grey);
  Light sun;
  sun.type = BAKEGI_LIGHT_SUN;
  sun.direction = glm::normalize(glm::vec3(-1, 0, -1));
  sun.color = glm::vec3(1.0f);
  d.lights.push_back(sun);
  return d;
}

struct Estimate {
  double mean = 0.0;
  uint64_t rays = 0;
};

// The lamps' light-sampled irradiance at a floor point, averaged over n samples.
Estimate sampled(const DirectLight& direct, const glm::vec3& position, int n) {
  const SurfacePoint x{position, {0, 0, 1}, {0, 0, 1}};
  Estimate e;
  for (int k = 0; k < n; ++k) {
    RandomStream rng = sample_stream(3, 0, uint64_t(k));
    e.mean += direct.sample_lights(x, rng, e.rays).x;
  }
  e.mean /= n;
  return e;
}

TEST(LampShadowCache, SkipsMostShadowRaysWhereBlockedAndStaysUnbiased) {
  const Scene scene = build_scene(room_with_a_hole());
  const RayTracer tracer(scene);
  DirectLight plain(scene, tracer), culled(scene, tracer);
  uint64_t pilot_rays = 0;
  // 4,096 pilot points over the room's 80 m^2, cells 2 m wide: the floor cell of the spot gets
  // about 200 of them, and its 2 cm spot (1e-4 of the cell) almost surely none.
  const LampShadowCache cache = LampShadowCache::build(scene, culled, pilot_rays, 4096, 2);
  culled.set_shadow_cache(&cache);
  EXPECT_GT(pilot_rays, 2000u);
  EXPECT_LE(pilot_rays, 4096u);

  const glm::vec3 up(0, 0, 1);
  const glm::vec3 spot(0.5f, 0.005f, 0.0f), dark(-1.0f, 1.0f, 0.0f);
  // The outside of the +x wall faces the sun: the pilot saw it there, so it is kept whole.
  EXPECT_EQ(cache.kept_probability(0, {2.0f, 1.0f, 1.0f}, {1, 0, 0}), 1.0f);
  ASSERT_EQ(cache.kept_probability(0, spot, up), LampShadowCache::kKeptWhereBlocked)
      << "the pilot found the spot's cell lit: the test's premise fails";
  EXPECT_EQ(cache.kept_probability(0, dark, up), LampShadowCache::kKeptWhereBlocked);
  EXPECT_GT(cache.blocked_shares().at(0), 0.0f);

  const int n = 65536;
  const double exact = std::sqrt(0.5);  // S cos 45 degrees
  const Estimate spot_plain = sampled(plain, spot, n), spot_culled = sampled(culled, spot, n);
  std::printf("spot: exact %.4f, every ray %.4f (%llu rays), culled %.4f (%llu rays)\n", exact,
              spot_plain.mean, (unsigned long long)spot_plain.rays, spot_culled.mean,
              (unsigned long long)spot_culled.rays);
  EXPECT_NEAR(spot_plain.mean, exact, 1e-5);
  // Kept 1 in 8 and weighed 8: relative spread sqrt(7 / n) = 1.0%; 4 sigma.
  EXPECT_NEAR(spot_culled.mean / exact, 1.0, 4.0 * std::sqrt(7.0 / n));
  EXPECT_NEAR(double(spot_culled.rays) / n, 0.125, 0.01);

  const Estimate dark_plain = sampled(plain, dark, n), dark_culled = sampled(culled, dark, n);
  EXPECT_EQ(dark_plain.mean, 0.0);
  EXPECT_EQ(dark_culled.mean, 0.0);
  EXPECT_EQ(dark_plain.rays, uint64_t(n));
  EXPECT_NEAR(double(dark_culled.rays) / n, 0.125, 0.01);

  // Deterministic: the same pilot gives the same cache.
  uint64_t again_rays = 0;
  const LampShadowCache again = LampShadowCache::build(scene, culled, again_rays, 4096, 2);
  EXPECT_EQ(again_rays, pilot_rays);
  EXPECT_EQ(again.blocked_shares(), cache.blocked_shares());
}

TEST(LampShadowCache, ALampWithoutShadowsAndASceneWithoutLampsAreNotJudged) {
  SceneDescription d = room_with_a_hole();
  d.lights[0].flags = BAKEGI_LIGHT_NO_SHADOW;
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  uint64_t rays = 0;
  const LampShadowCache cache = LampShadowCache::build(scene, direct, rays, 4096, 2);
  EXPECT_EQ(rays, 0u);
  EXPECT_EQ(cache.kept_probability(0, {-1.0f, 1.0f, 0.0f}, {0, 0, 1}), 1.0f);

  SceneDescription unlit = room_with_a_hole();
  unlit.lights.clear();
  unlit.world_radiance = glm::vec3(1.0f);
  const Scene sky_scene = build_scene(unlit);
  const RayTracer sky_tracer(sky_scene);
  const DirectLight sky(sky_scene, sky_tracer);
  const LampShadowCache none = LampShadowCache::build(sky_scene, sky, rays, 4096, 2);
  EXPECT_EQ(rays, 0u);
  EXPECT_TRUE(none.blocked_shares().empty());
}

}  // namespace
}  // namespace bakegi
