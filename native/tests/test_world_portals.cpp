// Window portals (lights/world_portals.h): the density of their samples, and a room lit by the
// sky through one window, whose light must be the same with a portal in the window as without
// it (Lambert's polygon formula gives the direct light exactly) and, at equal samples, less
// noisy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "api/handles.h"
#include "light_transport_fixtures.h"
#include "lights/world_portals.h"
#include "util/luminance.h"

namespace bakegi {
namespace {

// The window: x = 2, y in [-0.5, 0.5], z in [1, 2].
const glm::vec3 kWindowCenter(2.0f, 0.0f, 1.5f);

Light window_portal() {
  // Facing into the room (-x); size_x along y, size_y along (-x) x y = -z.
  Light portal = test::area_light(BAKEGI_AREA_RECTANGLE, kWindowCenter, {-1, 0, 0}, {0, 1, 0}, 1.0f,
                                  1.0f, glm::vec3(0.0f));
  return portal;
}

// A closed room [-2, 2] x [-2, 2] x [0, 3] of grey walls with one window in its +x wall.
SceneDescription room_with_window(bool with_portal) {
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(0.6f));
  const glm::vec3 y(0, 1, 0), z(0, 0, 1);
  test::add_room_without_plus_x_wall(d, grey);
  // The +x wall around the window.
  test::add_quad(d, {2, 0, 0.5f}, z, y, 0.5f, 2, grey);
  test::add_quad(d, {2, 0, 2.5f}, z, y, 0.5f, 2, grey);
  test::add_quad(d, {2, -1.25f, 1.5f}, z, y, 0.5f, 0.75f, grey);
  test::add_quad(d, {2, 1.25f, 1.5f}, z, y, 0.5f, 0.75f, grey);
  if (with_portal) d.portals.push_back(window_portal());
  return d;
}

// E / pi at p (normal n) from the window seen as a uniform emitter of radiance 1: Lambert's
// formula, (1 / 2 pi) |sum over edges of angle_i (n . unit(v_i x v_i+1))|.
double window_form_factor(const glm::dvec3& p, const glm::dvec3& n) {
  const glm::dvec3 corners[4] = {{2, -0.5, 1}, {2, 0.5, 1}, {2, 0.5, 2}, {2, -0.5, 2}};
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 a = glm::normalize(corners[i] - p);
    const glm::dvec3 b = glm::normalize(corners[(i + 1) % 4] - p);
    sum += std::acos(glm::clamp(glm::dot(a, b), -1.0, 1.0)) *
           glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return std::abs(sum) / (2.0 * M_PI);
}

const std::vector<glm::vec3> kPositions = {{0, 0, 0}, {-1, 1.2f, 0}, {-2, 0.3f, 1.4f}};
const std::vector<glm::vec3> kNormals = {{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};

TEST(WorldPortals, DensityIntegratesToTheShareOfPortalsSeenAndMatchesSamples) {
  // Two portals: the window, and one in the -x wall facing out of the room, which the point
  // sees from behind (its samples fail there): the density integrates to 1/2 over the sphere.
  Light behind = test::area_light(BAKEGI_AREA_DISK, {-2, 0, 1.5f}, {-1, 0, 0}, {0, 1, 0}, 0.8f,
                                  0.8f, glm::vec3(0.0f));
  const WorldPortals portals({window_portal(), behind});
  const glm::vec3 x(0.3f, -0.2f, 0.7f);
  ASSERT_TRUE(portals.seen_from(x));
  // The integral by the midpoint rule on a fine grid in (cos theta, phi): equal solid angles.
  const int n = 1000;
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const double cos_theta = 1.0 - 2.0 * (i + 0.5) / n,
                 sin_theta = std::sqrt(1 - cos_theta * cos_theta);
    for (int j = 0; j < n; ++j) {
      const double phi = 2.0 * M_PI * (j + 0.5) / n;
      const glm::vec3 d(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
      integral += portals.pdf(x, d);
    }
  }
  integral *= 4.0 * M_PI / (double(n) * n);
  std::printf("integral of the density: %.4f (expected 0.5)\n", integral);
  // The grid's cells are 1.3e-5 sr; the window subtends 0.2 sr: its edge cells err < 1%.
  EXPECT_NEAR(integral, 0.5, 0.01);

  int found = 0;
  for (int i = 0; i < 256; ++i) {
    glm::vec3 direction;
    float pdf = 0.0f;
    const float u0 = (i + 0.5f) / 256.0f, u1 = std::fmod(i * 0.618034f, 1.0f),
                u2 = std::fmod(i * 0.414214f, 1.0f);
    if (!portals.sample(x, u0, u1, u2, direction, pdf)) {
      EXPECT_GE(u0, 0.5f) << "the window is seen from x: its samples succeed";
      continue;
    }
    ++found;
    EXPECT_NEAR(pdf, portals.pdf(x, direction), 1e-3f * pdf);
    // Through the window, out of the room.
    const float t = (2.0f - x.x) / direction.x;
    const glm::vec3 at = x + t * direction;
    EXPECT_LE(std::abs(at.y), 0.5f + 1e-4f);
    EXPECT_NEAR(at.z, 1.5f, 0.5f + 1e-4f);
  }
  EXPECT_EQ(found, 128);
}

// E / pi at kPositions with the "direct" method: per seed and point.
std::vector<std::vector<double>> direct_light(const SceneDescription& d, int64_t samples,
                                              int seeds) {
  test::Baker baker(d);
  test::BakeOptions options;
  options.method = "direct";
  options.samples = samples;
  std::vector<std::vector<double>> values(kPositions.size());
  const BakePoints points = test::make_points(kPositions, kNormals);
  for (int seed = 0; seed < seeds; ++seed) {
    options.seed = seed;
    const std::vector<glm::vec3> out = baker.bake(points, options);
    for (size_t i = 0; i < out.size(); ++i) values[i].push_back(luminance(out[i]));
  }
  return values;
}

TEST(WorldPortals, SkyThroughAWindowMatchesLambertWithLessNoise) {
  for (bool image : {false, true}) {
    SceneDescription without = room_with_window(false), with = room_with_window(true);
    for (SceneDescription* d : {&without, &with}) {
      if (image) {
        // A uniform image world of radiance 1: sampled by the image and through the portal.
        d->world_texture.texture =
            test::add_texture(*d, 8, 4, [](uint32_t, uint32_t) { return glm::vec3(0.5f); });
        d->world_texture.scale = glm::vec3(2.0f);
      } else {
        d->world_radiance = glm::vec3(1.0f);
      }
    }
    const int seeds = 8;
    const auto a = direct_light(without, 64, seeds), b = direct_light(with, 64, seeds);
    for (size_t i = 0; i < kPositions.size(); ++i) {
      const double exact =
          window_form_factor(glm::dvec3(kPositions[i]), glm::normalize(glm::dvec3(kNormals[i])));
      const double spread_without = test::standard_deviation(a[i]) / exact;
      const double spread_with = test::standard_deviation(b[i]) / exact;
      std::printf(
          "%s world, point %zu: exact %.5f; without portal mean %.5f (spread %.3f), "
          "with %.5f (spread %.4f)\n",
          image ? "image" : "constant", i, exact, test::mean(a[i]), spread_without,
          test::mean(b[i]), spread_with);
      // With the portal every light sample finds the window: a few per cent per seed, so the
      // mean of 8 seeds is within 1.5% (several sigma).
      EXPECT_NEAR(test::mean(b[i]) / exact, 1.0, 0.015) << "point " << i;
      // Without it a cosine ray (or the image's sample over the sphere) finds the window
      // rarely: the noise at equal samples is several times larger.
      EXPECT_LT(spread_with * 3.0, spread_without) << "point " << i;
      // Both unbiased: their means differ by less than 4 sigma of the difference.
      const double sigma =
          std::sqrt((spread_without * spread_without + spread_with * spread_with) / seeds);
      EXPECT_NEAR(test::mean(a[i]) / exact, test::mean(b[i]) / exact, 4.0 * sigma) << "point " << i;
    }
  }
}

TEST(WorldPortals, ASunInTheImageIsStillFoundAndPathsAgree) {
  // An image with a bright sun texel that shines through the window onto the floor, and a dim
  // sky: half the world's light samples follow the image (the sun), half the portal. The path
  // tracer's indirect light with and without the portal must agree.
  // Texel (7, 5): 22.5 degrees wide around azimuth 11 and elevation 34 degrees, towards +x.
  auto sky = [](uint32_t i, uint32_t j) {
    return i == 7 && j == 5 ? glm::vec3(1.0f) : glm::vec3(0.02f);
  };
  SceneDescription without = room_with_window(false), with = room_with_window(true);
  for (SceneDescription* d : {&without, &with}) {
    d->world_texture.texture = test::add_texture(*d, 16, 8, sky);
    d->world_texture.scale = glm::vec3(20.0f);
  }
  const int seeds = 8;
  const auto a = direct_light(without, 1024, seeds), b = direct_light(with, 1024, seeds);
  for (size_t i = 0; i < kPositions.size(); ++i) {
    const double ma = test::mean(a[i]), mb = test::mean(b[i]);
    const double sa = test::standard_deviation(a[i]) / ma, sb = test::standard_deviation(b[i]) / mb;
    std::printf("sun: point %zu: direct without portal %.5f (spread %.3f), with %.5f (%.3f)\n", i,
                ma, sa, mb, sb);
    // Unbiased both ways: within 4 sigma of their difference.
    EXPECT_NEAR(mb / ma, 1.0, 4.0 * std::sqrt((sa * sa + sb * sb) / seeds)) << "point " << i;
  }

  test::BakeOptions options;
  options.samples = 16384;
  const BakePoints points = test::make_points(kPositions, kNormals);
  test::Baker without_baker(without), with_baker(with);
  std::vector<std::vector<double>> pa(points.size()), pb(points.size());
  const int path_seeds = 4;
  for (int seed = 0; seed < path_seeds; ++seed) {
    options.seed = seed;
    const std::vector<glm::vec3> va = without_baker.bake(points, options);
    const std::vector<glm::vec3> vb = with_baker.bake(points, options);
    for (size_t i = 0; i < points.size(); ++i) {
      pa[i].push_back(luminance(va[i]));
      pb[i].push_back(luminance(vb[i]));
    }
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const double ma = test::mean(pa[i]), mb = test::mean(pb[i]);
    const double sa = test::standard_deviation(pa[i]) / ma;
    const double sb = test::standard_deviation(pb[i]) / mb;
    std::printf("sun: point %zu: indirect without portal %.5f (spread %.3f), with %.5f (%.3f)\n", i,
                ma, sa, mb, sb);
    // 4 sigma of the difference, at least 2% (a spread from 4 seeds is itself uncertain).
    const double tolerance = std::max(0.02, 4.0 * std::sqrt((sa * sa + sb * sb) / path_seeds));
    EXPECT_NEAR(mb / ma, 1.0, tolerance) << "point " << i;
  }
}

TEST(WorldPortals, ApiTakesAreaShapesAndClearsThemWithTheLights) {
  bakegi_scene* raw = nullptr;
  ASSERT_EQ(bakegi_scene_create(&raw), BAKEGI_OK);
  std::unique_ptr<bakegi_scene, void (*)(bakegi_scene*)> scene(raw, bakegi_scene_destroy);
  bakegi_light_desc portal{};
  portal.type = BAKEGI_LIGHT_AREA;
  portal.shape = BAKEGI_AREA_RECTANGLE;
  portal.direction[0] = -1.0f;
  portal.axis_u[1] = 1.0f;
  portal.size_x = portal.size_y = 1.0f;
  portal.color[0] = 5.0f;
  EXPECT_EQ(bakegi_scene_add_portal(scene.get(), &portal), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_portal_count(scene.get()), 1u);
  EXPECT_EQ(bakegi_scene_light_count(scene.get()), 0u) << "a portal is not a light";
  EXPECT_EQ(scene->description.portals[0].color, glm::vec3(0.0f)) << "it emits nothing";

  bakegi_light_desc point = portal;
  point.type = BAKEGI_LIGHT_POINT;
  EXPECT_EQ(bakegi_scene_add_portal(scene.get(), &point), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("portal 1: a portal is an area light"),
            std::string::npos)
      << bakegi_last_error();
  bakegi_light_desc flat = portal;
  flat.size_x = 0.0f;
  EXPECT_EQ(bakegi_scene_add_portal(scene.get(), &flat), BAKEGI_ERROR_INVALID_SCENE);
  EXPECT_NE(std::string(bakegi_last_error()).find("portal 1: size_x"), std::string::npos)
      << bakegi_last_error();
  EXPECT_EQ(bakegi_scene_add_portal(scene.get(), nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_scene_portal_count(scene.get()), 1u);

  EXPECT_EQ(bakegi_scene_clear_lights(scene.get()), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_portal_count(scene.get()), 0u);
  EXPECT_EQ(bakegi_scene_portal_count(nullptr), 0u);
}

}  // namespace
}  // namespace bakegi
