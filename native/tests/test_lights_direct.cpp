// Direct light (method "direct", E_direct / pi) against closed forms for every light type,
// in the conventions of bakegi.h and Cycles 3.4.1 (see lights/*.h).
//
// Tolerances: delta lights (point, spot, sun with angle 0) have no Monte Carlo noise at
// all, so they are checked to float rounding (1e-4 relative; the ray-origin offset of
// 1e-5 x scene size is below that). Lights with a size are estimated by sampling; their
// tolerances are a few times the standard error measured over seeds at the sample counts
// used (given per test).
#include <gtest/gtest.h>

#include <cmath>

#include <cstdio>

#include "light_transport_fixtures.h"
#include "lights/emissive_triangles.h"
#include "scene/triangle_cells.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

using test::BakeOptions;
using test::Baker;

constexpr float kPlaneHalfSize = 50.0f;

// A large horizontal plane at z = 0 (normal +z) to receive light.
SceneDescription plane_scene() {
  SceneDescription d;
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  test::add_quad(d, glm::vec3(0.0f), {1, 0, 0}, {0, 1, 0}, kPlaneHalfSize, kPlaneHalfSize, grey);
  return d;
}

BakePoints points_on_plane(const std::vector<glm::vec2>& xy) {
  std::vector<glm::vec3> positions, normals;
  for (const auto& p : xy) {
    positions.emplace_back(p.x, p.y, 0.0f);
    normals.emplace_back(0.0f, 0.0f, 1.0f);
  }
  return test::make_points(positions, normals);
}

std::vector<glm::vec3> bake_direct(const SceneDescription& d, const BakePoints& points,
                                   int64_t samples, int64_t seed = 0) {
  Baker baker(d);
  BakeOptions options;
  options.method = "direct";
  options.samples = samples;
  options.seed = seed;
  return baker.bake(points, options);
}

void expect_relative(const glm::vec3& value, const glm::vec3& expected, double tolerance,
                     const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(value[c], expected[c], tolerance * std::abs(expected[c]))
        << what << ", channel " << c;
  }
}

// Form factor from a point to a parallel rectangle a x b at height c with one corner right
// above the point (Howell's catalogue): F = 1/(2 pi) [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) +
// Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))], X = a/c, Y = b/c. E = pi L F.
double corner_rectangle_form_factor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1.0 + x * x), sy = std::sqrt(1.0 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * M_PI);
}

// E / pi under a rectangle [x0, x1] x [y0, y1] at height h of radiance L, at the origin
// (which lies under it): four corner rectangles.
double rectangle_value_under(double x0, double x1, double y0, double y1, double h, double l) {
  double f = 0.0;
  for (double a : {-x0, x1}) {
    for (double b : {-y0, y1}) f += corner_rectangle_form_factor(a, b, h);
  }
  return l * f;  // E / pi = pi L F / pi
}

TEST(LightsDirect, PointLightOverPlaneIsIntensityCosineOverDistanceSquared) {
  SceneDescription d = plane_scene();
  const glm::vec3 intensity(10.0f, 5.0f, 2.5f);
  const float h = 2.0f;
  d.lights.push_back(test::point_light({0.0f, 0.0f, h}, intensity));
  const std::vector<glm::vec2> xy = {{0, 0}, {1, 0.5f}, {2, -1}, {4, 3}, {-7, 2}};
  const auto values = bake_direct(d, points_on_plane(xy), 4);
  for (size_t i = 0; i < xy.size(); ++i) {
    const float dist = std::sqrt(glm::dot(xy[i], xy[i]) + h * h);
    const float cosine = h / dist;
    expect_relative(values[i], intensity * (cosine / (kPi * dist * dist)), 1e-4,
                    "point " + std::to_string(i));
  }
}

TEST(LightsDirect, OccludedPointLightAndSunGiveNothing) {
  SceneDescription d = plane_scene();
  const uint32_t grey = test::add_material(d, glm::vec3(0.5f));
  test::add_quad(d, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1.0f, 1.0f, grey);  // a roof
  d.lights.push_back(test::point_light({0.0f, 0.0f, 3.0f}, glm::vec3(10.0f)));
  Light sun;
  sun.type = BAKEGI_LIGHT_SUN;
  sun.direction = {0, 0, -1};
  sun.color = glm::vec3(3.0f);
  d.lights.push_back(sun);
  const auto values = bake_direct(d, points_on_plane({{0, 0}, {0.5f, -0.5f}, {5, 0}}), 4);
  EXPECT_EQ(values[0], glm::vec3(0.0f));
  EXPECT_EQ(values[1], glm::vec3(0.0f));
  // Out of the roof's shadow both lights arrive.
  const float dist2 = 25.0f + 9.0f;
  const float expected = (3.0f + 10.0f * 3.0f / std::sqrt(dist2) / dist2) / kPi;
  EXPECT_NEAR(values[2].x, expected, 1e-4 * expected);
}

TEST(LightsDirect, LightsWithoutShadowsShineThroughTheRoof) {
  // Cast Shadow off (BAKEGI_LIGHT_NO_SHADOW): the roof of the test above no longer shadows
  // the point light, the sun or a small area light; each gives what it gives in the open.
  for (uint32_t type : {BAKEGI_LIGHT_POINT, BAKEGI_LIGHT_SUN, BAKEGI_LIGHT_AREA}) {
    SceneDescription open = plane_scene();
    Light light;
    if (type == BAKEGI_LIGHT_POINT) light = test::point_light({0.0f, 0.0f, 3.0f}, glm::vec3(10.0f));
    if (type == BAKEGI_LIGHT_SUN) {
      light.type = BAKEGI_LIGHT_SUN;
      light.direction = {0, 0, -1};
      light.color = glm::vec3(3.0f);
    }
    if (type == BAKEGI_LIGHT_AREA) {
      light = test::area_light(BAKEGI_AREA_SQUARE, {0, 0, 3}, {0, 0, -1}, {1, 0, 0}, 0.2f, 0.2f,
                               glm::vec3(50.0f));
    }
    open.lights.push_back(light);
    SceneDescription roofed = open;
    const uint32_t grey = test::add_material(roofed, glm::vec3(0.5f));
    test::add_quad(roofed, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1.0f, 1.0f, grey);
    roofed.lights[0].flags = BAKEGI_LIGHT_NO_SHADOW;
    const BakePoints points = points_on_plane({{0, 0}, {0.5f, -0.5f}});
    const auto expected = bake_direct(open, points, 4);
    const auto got = bake_direct(roofed, points, 4);
    for (size_t i = 0; i < points.size(); ++i) {
      EXPECT_GT(expected[i].x, 0.0f);
      // The same light samples; the area light's cosine rays, which hit the roof first,
      // differ (weighted by MIS against the light samples, as in Cycles): a few per cent.
      const float tolerance = type == BAKEGI_LIGHT_AREA ? 0.05f : 1e-4f;
      EXPECT_NEAR(got[i].x, expected[i].x, tolerance * expected[i].x)
          << "light type " << type << ", point " << i;
    }
  }
}

TEST(LightsDirect, AreaSpreadKeepsThePowerAndConcentratesItOnTheAxis) {
  // A 0.1 m square light of radiance 10, 1 m over the plane, facing down, spread 60 degrees
  // (h = 30): on the axis the radiance is L f(0) = L tan h / (tan h - h); off the cone
  // (tan a > tan h) nothing; over the plane the power is the Lambertian pi L A.
  SceneDescription d = plane_scene();
  Light light = test::area_light(BAKEGI_AREA_SQUARE, {0, 0, 1}, {0, 0, -1}, {1, 0, 0}, 0.1f, 0.1f,
                                 glm::vec3(10.0f));
  light.spot_size = float(kPi / 3.0);
  d.lights.push_back(light);
  const double h = kPi / 6.0, boost = std::tan(h) / (std::tan(h) - h);
  std::vector<glm::vec2> grid;
  const int n = 61;
  const float step = 2.4f / float(n - 1);  // [-1.2, 1.2]^2: the lit disk has radius 0.58 + 0.07
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) grid.push_back({-1.2f + step * i, -1.2f + step * j});
  }
  grid.push_back({0.0f, 0.0f});
  grid.push_back({0.8f, 0.0f});  // tan a = 0.8 > tan 30 + the light's half width
  const auto values = bake_direct(d, points_on_plane(grid), 64);
  double power = 0.0;
  for (int k = 0; k < n * n; ++k) power += double(values[size_t(k)].x) * kPi * step * step;
  const double lambertian = kPi * 10.0 * 0.01;
  // On the axis: E / pi = (1 / pi) integral over the light of L f(a) cos^2 / d^2 (the light
  // parallel to the plane, so both cosines are 1 / d), by the midpoint rule.
  double on_axis = 0.0;
  const int m = 200;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const double x = 0.1 * ((i + 0.5) / m - 0.5), y = 0.1 * ((j + 0.5) / m - 0.5);
      const double d2 = x * x + y * y + 1.0, tan_a = std::sqrt(x * x + y * y);
      const double f = std::max(std::tan(h) - tan_a, 0.0) / (std::tan(h) - h);
      on_axis += 10.0 * f / (d2 * d2) * (0.1 / m) * (0.1 / m) / kPi;
    }
  }
  std::printf("power %.5f, Lambertian %.5f; on axis %.4f, expected %.4f (f(0) alone: %.4f)\n",
              power, lambertian, values[size_t(n * n)].x, on_axis, 10.0 * boost * 0.01 / kPi);
  EXPECT_NEAR(power / lambertian, 1.0, 0.02);  // the midpoint rule on a 4 cm grid
  EXPECT_NEAR(values[size_t(n * n)].x / on_axis, 1.0, 0.01);
  EXPECT_EQ(values[size_t(n * n + 1)].x, 0.0f);
}

TEST(LightsDirect, SunGivesIrradianceTimesCosine) {
  const float theta = glm::radians(30.0f);
  const glm::vec3 travel(-std::sin(theta), 0.0f, -std::cos(theta));
  const glm::vec3 irradiance(4.0f, 2.0f, 1.0f);
  const auto points = points_on_plane({{0, 0}, {3, -2}});
  {
    SceneDescription d = plane_scene();
    Light sun;
    sun.type = BAKEGI_LIGHT_SUN;
    sun.direction = travel;
    sun.color = irradiance;
    d.lights.push_back(sun);
    const auto values = bake_direct(d, points, 4);
    for (const auto& v : values)
      expect_relative(v, irradiance * std::cos(theta) / kPi, 1e-4, "sun");
  }
  {
    // A sun disc 10 degrees across, sampled as Cycles does (a disk of radius T = tan(5 deg)
    // at unit distance with density 1 / (A cos^3)): each sample carries S cos(n, w), and
    // averaging cos over the disk gives S cos(theta) * 2 (sqrt(1 + T^2) - 1) / T^2 (the
    // tangential part averages out; the whole disc is above the horizon). The integrand
    // varies by < 1% over the disc: 256 samples leave < 0.05% noise; tolerance 0.2%.
    SceneDescription d = plane_scene();
    Light sun;
    sun.type = BAKEGI_LIGHT_SUN;
    sun.direction = travel;
    sun.color = irradiance;
    sun.angle = glm::radians(10.0f);
    d.lights.push_back(sun);
    const auto values = bake_direct(d, points, 256);
    const double t = std::tan(0.5 * sun.angle);
    const double disc_mean_cos = 2.0 * (std::sqrt(1.0 + t * t) - 1.0) / (t * t);
    for (const auto& v : values) {
      expect_relative(v, irradiance * float(std::cos(theta) * disc_mean_cos / M_PI), 2e-3,
                      "sun disc");
    }
  }
}

// Cycles 3.4.1 spot: intensity I on the axis, times a = cos(angle to the axis) inside the
// cone, times smoothstep in the blend band, zero outside (lights/spot_light.h). With
// BAKEGI_LIGHT_SPOT_WITHOUT_COSINE (Cycles 4.0+) the same without the factor a.
class SpotCones : public ::testing::TestWithParam<bool> {};

TEST_P(SpotCones, ConeAndBlendBand) {
  const bool cosine = GetParam();
  SceneDescription d = plane_scene();
  const float h = 2.0f;
  Light spot = test::point_light({0.0f, 0.0f, h}, glm::vec3(20.0f));
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.direction = {0, 0, -1};
  spot.spot_size = glm::radians(60.0f);
  spot.spot_blend = 0.5f;
  spot.flags = cosine ? 0u : BAKEGI_LIGHT_SPOT_WITHOUT_COSINE;
  d.lights.push_back(spot);
  const double cos_half = std::cos(0.5 * spot.spot_size);
  const double smooth = (1.0 - cos_half) * spot.spot_blend;
  // Angles off the axis: inside, through the band (acos(cos_half + smooth) ~ 21.5 deg up to
  // 30 deg), and outside.
  std::vector<double> angles_deg = {0, 10, 20, 21, 22, 24, 26, 28, 29.5, 31, 45};
  std::vector<glm::vec2> xy;
  for (double a : angles_deg) xy.emplace_back(float(h * std::tan(glm::radians(a))), 0.0f);
  const auto values = bake_direct(d, points_on_plane(xy), 4);
  for (size_t i = 0; i < angles_deg.size(); ++i) {
    const double a = std::cos(glm::radians(angles_deg[i]));
    double attenuation = 0.0;
    if (a > cos_half) {
      const double t = (a - cos_half) / smooth;
      const double falloff = cosine ? a : 1.0;
      attenuation = t < 1.0 ? falloff * t * t * (3.0 - 2.0 * t) : falloff;
    }
    const double dist = h / a;
    const double expected = 20.0 * attenuation * a / (dist * dist) / M_PI;
    EXPECT_NEAR(values[i].x, expected, 1e-4 * expected + 1e-9) << angles_deg[i] << " degrees";
    if (i > 0) EXPECT_LT(values[i].x, values[i - 1].x + 1e-9) << "not monotone in the band";
  }
  EXPECT_GT(values[4].x, 0.0f);  // in the band: lit, but less than the cone inside
  EXPECT_EQ(values[9].x, 0.0f);  // outside the cone
  EXPECT_EQ(values[10].x, 0.0f);
}

INSTANTIATE_TEST_SUITE_P(LightsDirect, SpotCones, ::testing::Values(true, false),
                         [](const auto& info) {
                           return info.param ? "Cycles3WithCosine" : "Cycles4WithoutCosine";
                         });

TEST(LightsDirect, SphereLightIsADiskFacingThePoint) {
  // A point light of radius r is a disk of radiance I / (pi r^2) facing the shading point:
  // E = I cos(theta) / (r^2 + D^2) with D the distance to the centre and theta the tilt of
  // the receiver (exact while the whole disk is above the horizon). 1024 samples: 0.09% and
  // 0.19% standard deviation over 40 seeds at the two points; tolerance 1%.
  SceneDescription d = plane_scene();
  const float h = 2.0f, r = 0.5f;
  d.lights.push_back(test::point_light({0.0f, 0.0f, h}, glm::vec3(10.0f), r));
  const std::vector<glm::vec2> xy = {{0, 0}, {1.5f, 0}};
  const auto values = bake_direct(d, points_on_plane(xy), 1024);
  for (size_t i = 0; i < xy.size(); ++i) {
    const float dist2 = glm::dot(xy[i], xy[i]) + h * h;
    const float cosine = h / std::sqrt(dist2);
    expect_relative(values[i], glm::vec3(10.0f * cosine / (r * r + dist2) / kPi), 1e-2,
                    "sphere light, point " + std::to_string(i));
  }
}

TEST(LightsDirect, SmallAreaLightsApproachPointLightsOfIntensityLACos) {
  // Far away, a Lambertian emitter of radiance L and area A is a point of intensity
  // L A cos(angle to its normal): E = L A cos_l cos_r / d^2, up to (size / d)^2 ~ 1e-3.
  // The samples differ by ~size / d ~ 3%: 64 samples leave ~0.3% noise. Tolerance 1%.
  const glm::vec3 radiance(3.0f, 2.0f, 1.0f);
  const float h = 10.0f;
  struct Shape {
    bakegi_area_shape shape;
    float sx, sy, area;
  };
  const Shape shapes[] = {{BAKEGI_AREA_SQUARE, 0.2f, 0.0f, 0.04f},
                          {BAKEGI_AREA_RECTANGLE, 0.3f, 0.1f, 0.03f},
                          {BAKEGI_AREA_DISK, 0.2f, 0.0f, kPi * 0.01f},
                          {BAKEGI_AREA_ELLIPSE, 0.3f, 0.1f, kPi * 0.15f * 0.05f}};
  const std::vector<glm::vec2> xy = {{0, 0}, {3, 4}};
  for (const Shape& s : shapes) {
    SceneDescription d = plane_scene();
    d.lights.push_back(
        test::area_light(s.shape, {0, 0, h}, {0, 0, -1}, {1, 0, 0}, s.sx, s.sy, radiance));
    const auto values = bake_direct(d, points_on_plane(xy), 64);
    for (size_t i = 0; i < xy.size(); ++i) {
      const float dist2 = glm::dot(xy[i], xy[i]) + h * h;
      const float cosine = h / std::sqrt(dist2);
      expect_relative(values[i], radiance * (s.area * cosine * cosine / dist2 / kPi), 1e-2,
                      "shape " + std::to_string(int(s.shape)) + ", point " + std::to_string(i));
    }
  }
}

TEST(LightsDirect, AreaLightsAreOneSided) {
  SceneDescription d = plane_scene();
  // Facing up, away from the plane: nothing reaches it.
  d.lights.push_back(test::area_light(BAKEGI_AREA_SQUARE, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}, 1.0f,
                                      0.0f, glm::vec3(5.0f)));
  const auto values = bake_direct(d, points_on_plane({{0, 0}, {2, 0}}), 16);
  EXPECT_EQ(values[0], glm::vec3(0.0f));
  EXPECT_EQ(values[1], glm::vec3(0.0f));
}

TEST(LightsDirect, DiskLightOnAxisClosedForm) {
  // On the axis of a disk of radius r at height h: E = pi L r^2 / (r^2 + h^2). A large,
  // close disk (r = h) is the hard case for area sampling; with MIS, 4096 samples give 0.6%
  // standard deviation over seeds (1.2% measured at 1024). Tolerance 2.5%.
  SceneDescription d = plane_scene();
  const float r = 1.0f, h = 1.0f;
  const glm::vec3 radiance(2.0f, 1.0f, 0.5f);
  d.lights.push_back(test::area_light(BAKEGI_AREA_DISK, {0, 0, h}, {0, 0, -1}, {1, 0, 0}, 2.0f * r,
                                      0.0f, radiance));
  const auto values = bake_direct(d, points_on_plane({{0, 0}}), 4096);
  expect_relative(values[0], radiance * (r * r / (r * r + h * h)), 2.5e-2, "disk on axis");
}

TEST(LightsDirect, RectangleLightClosedFormChecksItsAxes) {
  // A 2 x 0.2 rectangle, long along axis_u = x, at height 0.5; points under it are
  // checked against the corner-rectangle form factors. Were the axes swapped, the point
  // under its far end (x = 0.8) would be in the dark. 1024 samples: 0.65% standard
  // deviation over 40 seeds (solid-angle sampling); tolerance 3%.
  SceneDescription d = plane_scene();
  const float h = 0.5f;
  const glm::vec3 radiance(4.0f);
  d.lights.push_back(test::area_light(BAKEGI_AREA_RECTANGLE, {0, 0, h}, {0, 0, -1}, {1, 0, 0}, 2.0f,
                                      0.2f, radiance));
  const std::vector<glm::vec2> xy = {{0, 0}, {0.8f, 0.05f}};
  const auto values = bake_direct(d, points_on_plane(xy), 1024);
  for (size_t i = 0; i < xy.size(); ++i) {
    const double expected =
        rectangle_value_under(-1.0 - xy[i].x, 1.0 - xy[i].x, -0.1 - xy[i].y, 0.1 - xy[i].y, h, 4.0);
    EXPECT_NEAR(values[i].x, expected, 3e-2 * expected) << "point " << i;
  }
}

TEST(LightsDirect, EmissiveTrianglesEqualAnAreaLightOfTheSameShape) {
  // A 1 x 1 square of radiance L at height 0.5 as two one-sided emissive triangles facing
  // down, against the same square as an area light and the closed form. Standard
  // deviations over 40 seeds at 1024 samples: 1.5-2.3% for the triangles (area sampling),
  // 0.6-0.8% for the lamp (solid-angle sampling); at 8192 samples the triangles' is < 0.8%
  // and the lamp's < 0.3%. Tolerance 3%.
  const float h = 0.5f;
  const glm::vec3 radiance(3.0f, 1.5f, 0.75f);
  const std::vector<glm::vec2> xy = {{0, 0}, {0.3f, -0.2f}, {1.5f, 0.5f}};
  const auto points = points_on_plane(xy);

  SceneDescription mesh_light = plane_scene();
  const uint32_t emitter = test::add_material(mesh_light, glm::vec3(0.0f), radiance, false);
  // u x v = (1,0,0) x (0,-1,0) = (0,0,-1): the face normal points down at the plane.
  test::add_quad(mesh_light, {0, 0, h}, {1, 0, 0}, {0, -1, 0}, 0.5f, 0.5f, emitter);
  const auto from_triangles = bake_direct(mesh_light, points, 8192);

  SceneDescription lamp = plane_scene();
  lamp.lights.push_back(
      test::area_light(BAKEGI_AREA_SQUARE, {0, 0, h}, {0, 0, -1}, {1, 0, 0}, 1.0f, 0.0f, radiance));
  const auto from_lamp = bake_direct(lamp, points, 8192);

  for (size_t i = 0; i < xy.size(); ++i) {
    expect_relative(from_triangles[i], from_lamp[i], 3e-2, "point " + std::to_string(i));
  }
  for (size_t i = 0; i < 2; ++i) {
    const double expected = rectangle_value_under(-0.5 - xy[i].x, 0.5 - xy[i].x, -0.5 - xy[i].y,
                                                  0.5 - xy[i].y, h, radiance.x);
    EXPECT_NEAR(from_triangles[i].x, expected, 3e-2 * expected) << "point " << i;
    EXPECT_NEAR(from_lamp[i].x, expected, 2e-2 * expected) << "point " << i;
  }
}

TEST(LightsDirect, OneSidedEmissionLightsOnlyItsFrontTwoSidedBoth) {
  // Points above an emitter facing down see its back: dark if one-sided, and the same as
  // below if two-sided (Cycles 3.4 mesh emission). Checked against the closed form for a
  // 1 x 1 square at distance 0.5; 8192 samples leave < 0.8% noise (see above), tolerance 3%.
  const glm::vec3 radiance(2.0f);
  auto scene_with = [&](bool two_sided) {
    SceneDescription d = plane_scene();
    const uint32_t emitter = test::add_material(d, glm::vec3(0.0f), radiance, two_sided);
    test::add_quad(d, {0, 0, 1}, {1, 0, 0}, {0, -1, 0}, 0.5f, 0.5f, emitter);
    return d;
  };
  // A point 0.5 below the emitter facing up, and one 0.5 above it facing down.
  const auto points = test::make_points({{0, 0, 0.5f}, {0, 0, 1.5f}}, {{0, 0, 1}, {0, 0, -1}});
  const auto one_sided = bake_direct(scene_with(false), points, 8192);
  const auto two_sided = bake_direct(scene_with(true), points, 8192);
  const double expected = rectangle_value_under(-0.5, 0.5, -0.5, 0.5, 0.5, 2.0);
  EXPECT_NEAR(one_sided[0].x, expected, 0.03 * expected);
  EXPECT_EQ(one_sided[1].x, 0.0f);
  EXPECT_NEAR(two_sided[0].x, expected, 0.03 * expected);
  EXPECT_NEAR(two_sided[1].x, expected, 0.03 * expected);
}

// A 1 x 1 emitter facing down at height 0.5 over the plane whose 64 x 64 emission texture is
// white in one quadrant (texels i, j >= 32) and black elsewhere. Its UVs run from the centre
// of the first texel to the centre of the last, so bilinear filtering blends only across the
// quadrant's two inner edges, over 1/63 of the quad, symmetrically: against a sharp edge that
// moves no power and shifts the light by a second-order amount (about 2e-5 here).
// u runs along +x and v along -y, so the white quadrant is x in [0, 0.5], y in [-0.5, 0].
SceneDescription quadrant_emitter_scene(const glm::vec3& emission) {
  SceneDescription d = plane_scene();
  const uint32_t texture = test::add_texture(d, 64, 64, [](uint32_t i, uint32_t j) {
    return glm::vec3(i >= 32 && j >= 32 ? 1.0f : 0.0f);
  });
  const uint32_t emitter = test::add_material(d, glm::vec3(0.0f), emission, false);
  d.materials[emitter].emission_texture = texture;
  const float edge = 0.5f / 64.0f;
  test::add_quad_with_uvs(d, {0, 0, 0.5f}, {1, 0, 0}, {0, -1, 0}, 0.5f, 0.5f, emitter,
                          glm::vec2(edge), glm::vec2(1.0f - edge));
  return d;
}

TEST(LightsDirect, TexturedEmitterIsItsLitPartAsAnUntexturedEmitter) {
  // The quadrant emitter against (a) the closed form of its white quadrant alone and (b) an
  // untextured emitter of that quadrant's shape, at points under the white quadrant, under
  // black, on its corner and outside, so that the texture's orientation (rows from v = 0, u
  // along corner 0 -> 1) is checked too: with v flipped the points at (0.25, -0.25) and
  // (0.25, 0.25) would swap light and dark, with u flipped those at (0.25, -0.25) and
  // (-0.25, -0.25) (3-10x changes). Light sampling picks only the white cells
  // (emission_cells.h) and the cosine rays weigh their hits with the same cell densities,
  // so an inconsistency between the two halves of MIS shows as bias (cells looked up with
  // b1 and b2 swapped: 47-49% off). Noise, relative standard deviation over 10 seeds at 8192
  // samples: 0.4-0.9% per point; at the 16384 used here <= 0.65%, <= 0.9% for the
  // difference of two bakes. Tolerance 3% (>= 3.3 standard deviations).
  const glm::vec3 emission(3.0f, 1.5f, 0.75f);
  const std::vector<glm::vec2> xy = {
      {0.25f, -0.25f}, {0.25f, 0.25f}, {-0.25f, -0.25f}, {0, 0}, {1.0f, -0.3f}};
  const auto points = points_on_plane(xy);
  const auto textured = bake_direct(quadrant_emitter_scene(emission), points, 16384);

  SceneDescription quadrant = plane_scene();
  test::add_quad(quadrant, {0.25f, -0.25f, 0.5f}, {1, 0, 0}, {0, -1, 0}, 0.25f, 0.25f,
                 test::add_material(quadrant, glm::vec3(0.0f), emission, false));
  const auto untextured = bake_direct(quadrant, points, 16384);

  for (size_t i = 0; i < xy.size(); ++i) {
    const double expected = rectangle_value_under(0.0 - xy[i].x, 0.5 - xy[i].x, -0.5 - xy[i].y,
                                                  0.0 - xy[i].y, 0.5, 1.0);
    const std::string what = "point " + std::to_string(i);
    expect_relative(textured[i], emission * float(expected), 3e-2, what + " (closed form)");
    expect_relative(textured[i], untextured[i], 3e-2, what + " (untextured quadrant)");
  }
}

TEST(LightsDirect, TexturedEmitterSamplesItsBrightCellsWithConsistentDensities) {
  // A mostly black texture (an 8 x 8 texel white square in 64 x 64: 1.6% of the emitter)
  // must not waste light samples: picking triangles by their mean emission alone would land
  // on the white square 1.6% of the time; picking cells (about 2 x 2 texels) lands on light
  // nearly always, all but the samples in cells that straddle the square's blurred edge.
  // And pdf(), which the cosine rays' MIS weights use, must be the density sample() draws
  // from: it integrates to 1 over the emitters (exactly: it is constant on each cell, so
  // the centroids of a grid 3x finer than every cell's integrate it without error), and at
  // every sampled point it gives the sample's own density.
  SceneDescription d = plane_scene();
  const uint32_t texture = test::add_texture(d, 64, 64, [](uint32_t i, uint32_t j) {
    return glm::vec3(i >= 40 && i < 48 && j >= 20 && j < 28 ? 1.0f : 0.0f);
  });
  const uint32_t emitter = test::add_material(d, glm::vec3(0.0f), glm::vec3(2.0f), true);
  d.materials[emitter].emission_texture = texture;
  test::add_quad_with_uvs(d, {0, 0, 1.0f}, {1, 0, 0}, {0, -1, 0}, 0.5f, 0.5f, emitter,
                          glm::vec2(0.0f), glm::vec2(1.0f));
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  const EmissiveTriangles emitters(scene);

  double integral = 0.0;
  for (size_t e = 0; e < scene.emissive_triangles.size(); ++e) {
    const uint32_t index = scene.emissive_triangles[e];
    const Triangle& t = scene.triangles[index];
    const uint32_t fine = 3 * scene.emission_cells.level[e];
    for (uint32_t c = 0; c < triangle_cell_count(fine); ++c) {
      const auto corners = triangle_cell_corners(fine, c);
      const glm::vec2 b = (corners[0] + corners[1] + corners[2]) / 3.0f;
      integral += double(emitters.pdf(index, b.x, b.y, 1.0f, 1.0f)) * t.area / (fine * fine);
    }
  }
  EXPECT_NEAR(integral, 1.0, 1e-4);

  const glm::vec3 receiver(0.1f, 0.2f, 0.0f);
  Pcg32 rng(7, 1);
  int lit = 0, mismatched = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    LightSample s;
    const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    if (!emitters.sample(receiver, u0, u1, u2, s)) continue;
    ++lit;
    // From off the plane, which the receiver lies on.
    const Hit hit = tracer.intersect(Ray{receiver, s.direction, 1e-4f, 1e30f});
    ASSERT_TRUE(hit.hit);
    ASSERT_TRUE(scene.material_of(scene.triangles[hit.triangle]).is_emissive());
    const float cos_light =
        std::abs(glm::dot(scene.triangles[hit.triangle].face_normal, s.direction));
    const float pdf = emitters.pdf(hit.triangle, hit.b1, hit.b2, hit.t, cos_light);
    if (std::abs(pdf / s.pdf - 1.0f) > 1e-3f) ++mismatched;  // a cell edge, by rounding
  }
  std::printf("lit samples %.1f%%, pdf mismatches %d of %d\n", 100.0 * lit / n, mismatched, lit);
  EXPECT_GT(lit, n * 80 / 100);  // measured 92.1%; 3.9% with one cell per triangle
  EXPECT_LE(mismatched, lit / 1000);
}

TEST(LightsDirect, ConstantWorldOverAPlaneIsItsRadiance) {
  // Every cosine-sampled ray from an upward-facing plane leaves the scene and carries
  // pi L_world, so E / pi = L_world with no noise at all.
  SceneDescription d = plane_scene();
  d.world_radiance = glm::vec3(0.25f, 0.5f, 1.0f);
  const auto values = bake_direct(d, points_on_plane({{0, 0}, {10, -20}}), 8);
  for (const auto& v : values) expect_relative(v, d.world_radiance, 1e-5, "world");
}

}  // namespace
}  // namespace bakegi
