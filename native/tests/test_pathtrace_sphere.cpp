// The path tracer inside a closed diffuse sphere, where indirect light has a closed form.
//
// Point light of intensity I at the centre of a sphere of radius R and albedo rho. The
// direct irradiance on the wall is E0 = I / R^2 everywhere. The wall then reflects a
// uniform radiance L1 = rho E0 / pi, and a closed enclosure of uniform radiance L gives
// irradiance pi L at every point (every direction sees the wall). So the k-th bounce adds
// E_k = rho E_{k-1} = rho^k E0, and the indirect irradiance is
//   E_ind = E0 (rho + rho^2 + ...) = E0 rho / (1 - rho);
// the bake value (E_ind / pi) is rho I / (pi R^2 (1 - rho)), the same at every point.
// With max_bounces = 1 only the first term remains: rho I / (pi R^2).
//
// Tessellation: on an icosphere the walls lie slightly inside the sphere (by up to
// 1 - cos of the triangles' circumradius angle, 7e-4 R for 4 subdivisions), so the direct
// irradiance is not exactly I / R^2. All of the lamp's 4 pi I watts land on the walls, so
// their mean direct irradiance is exactly 4 pi I / A_mesh; the expected values below use
// that instead of I / R^2 (a 0.1% correction, second-order errors remain).
//
// Furnace: a closed sphere of uniform two-sided emission Le and albedo rho, no lamps. Any
// closed enclosure then holds uniform radiance L = Le + rho L, so L = Le / (1 - rho)
// (exact for any tessellation), of which Le arrives directly: the indirect value is
// L - Le = Le rho / (1 - rho).
#include <gtest/gtest.h>

#include <cmath>

#include "light_transport_fixtures.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

using test::BakeOptions;
using test::Baker;

constexpr float kRadius = 1.5f;
constexpr int kSubdivisions = 4;  // 5120 triangles

// Bake points at random places on the sphere's triangles, facing the centre.
BakePoints points_inside(const Mesh& sphere, int count) {
  std::vector<glm::vec3> positions, normals;
  Pcg32 rng(12345, 678);
  const size_t triangles = sphere.indices.size() / 3;
  for (int i = 0; i < count; ++i) {
    const size_t t = std::min(size_t(rng.next_float() * float(triangles)), triangles - 1);
    const glm::vec3 a = sphere.positions[sphere.indices[3 * t]];
    const glm::vec3 b = sphere.positions[sphere.indices[3 * t + 1]];
    const glm::vec3 c = sphere.positions[sphere.indices[3 * t + 2]];
    const glm::vec2 bary = sample_triangle_barycentrics(rng.next_float(), rng.next_float());
    positions.push_back(a * (1.0f - bary.x - bary.y) + b * bary.x + c * bary.y);
    normals.push_back(-glm::normalize(glm::cross(b - a, c - a)));  // inward
  }
  return test::make_points(positions, normals);
}

struct Statistics {
  glm::dvec3 mean{0.0};
  glm::dvec3 standard_error{0.0};  // of the mean over points
  glm::dvec3 max_relative_deviation{0.0};
};

Statistics statistics(const std::vector<glm::vec3>& values, const glm::dvec3& expected) {
  Statistics s;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> channel;
    for (const auto& v : values) channel.push_back(v[c]);
    s.mean[c] = test::mean(channel);
    s.standard_error[c] = test::standard_deviation(channel) / std::sqrt(double(channel.size()));
    for (double x : channel) {
      s.max_relative_deviation[c] =
          std::max(s.max_relative_deviation[c], std::abs(x / expected[c] - 1.0));
    }
  }
  return s;
}

TEST(PathTraceSphere, PointLightAtCentreGivesClosedFormIndirect) {
  // Coloured albedo: each channel is its own geometric series, and Russian roulette
  // (driven by the largest channel) must stay unbiased for all of them.
  const glm::vec3 albedo(0.3f, 0.5f, 0.7f);
  const glm::vec3 intensity(4.0f, 2.0f, 1.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, albedo);
  d.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), kRadius, kSubdivisions, wall));
  d.lights.push_back(test::point_light(glm::vec3(0.0f), intensity));
  const double area = test::mesh_area(d.meshes[0]);
  const glm::dvec3 mean_direct = glm::dvec3(intensity) * (4.0 * M_PI / area);
  const glm::dvec3 rho(albedo);
  const glm::dvec3 expected = rho * mean_direct / (M_PI * (1.0 - rho));

  Baker baker(d);
  const BakePoints points = points_inside(d.meshes[0], 128);
  BakeOptions options;
  options.samples = 512;
  const auto values = baker.bake(points, options);
  const Statistics s = statistics(values, expected);
  for (int c = 0; c < 3; ++c) {
    // Measured standard errors of the mean over 128 points x 512 paths (printed below):
    // 0.01%, 0.05% and 0.21% of the value for albedo 0.3, 0.5, 0.7 (Russian roulette is
    // the only noise here). 1% is the bound and > 5 standard errors; the noise
    // itself must stay below 0.4% (else roulette or sampling got worse).
    EXPECT_NEAR(s.mean[c], expected[c], 0.01 * expected[c]) << "channel " << c;
    EXPECT_LT(s.standard_error[c], 0.004 * expected[c]) << "channel " << c;
    // Uniform: every point within 12% (per-point standard deviation <= 2.1%, so > 5 of
    // them; a light leak or a missing bounce at some points would show here).
    EXPECT_LT(s.max_relative_deviation[c], 0.12) << "channel " << c;
  }
  std::printf("sphere: expected %.6f %.6f %.6f, mean %.6f %.6f %.6f, stderr %.2e %.2e %.2e\n",
              expected.x, expected.y, expected.z, s.mean.x, s.mean.y, s.mean.z, s.standard_error.x,
              s.standard_error.y, s.standard_error.z);
}

TEST(PathTraceSphere, MaxBouncesOneKeepsOnlyTheFirstBounce) {
  // With one reflecting vertex the value is rho E0 / pi; with the lamp exactly at the
  // centre the only noise is the tessellation's (the light sample is exact), so the mean
  // over points is well inside 0.5%.
  const glm::vec3 albedo(0.6f);
  const glm::vec3 intensity(3.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, albedo);
  d.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), kRadius, kSubdivisions, wall));
  d.lights.push_back(test::point_light(glm::vec3(0.0f), intensity));
  const double area = test::mesh_area(d.meshes[0]);
  const double expected = 0.6 * 3.0 * (4.0 * M_PI / area) / M_PI;

  Baker baker(d);
  BakeOptions options;
  options.samples = 16;
  options.max_bounces = 1;
  const auto values = baker.bake(points_inside(d.meshes[0], 64), options);
  const Statistics s = statistics(values, glm::dvec3(expected));
  EXPECT_NEAR(s.mean.x, expected, 0.005 * expected);
  EXPECT_LT(s.max_relative_deviation.x, 0.01);

  options.max_bounces = 2;  // rho E0 (1 + rho) / pi
  const auto two = baker.bake(points_inside(d.meshes[0], 64), options);
  const Statistics s2 = statistics(two, glm::dvec3(expected * 1.6));
  EXPECT_NEAR(s2.mean.x, expected * 1.6, 0.01 * expected * 1.6);
}

TEST(PathTraceSphere, FurnaceWithEmissiveWalls) {
  const float rho = 0.5f;
  const glm::vec3 emission(1.0f, 0.5f, 2.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, glm::vec3(rho), emission, true);
  d.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), kRadius, 3, wall));
  const glm::dvec3 expected = glm::dvec3(emission) * double(rho / (1.0f - rho));

  Baker baker(d);
  BakeOptions options;
  options.samples = 128;
  const auto values = baker.bake(points_inside(d.meshes[0], 128), options);
  const Statistics s = statistics(values, expected);
  for (int c = 0; c < 3; ++c) {
    // Standard error of the mean 0.19% (printed below); 1% bound (> 5 standard errors).
    // Per-point standard deviation 2.2%: all within 12%.
    EXPECT_NEAR(s.mean[c], expected[c], 0.01 * expected[c]) << "channel " << c;
    EXPECT_LT(s.max_relative_deviation[c], 0.12) << "channel " << c;
  }
  std::printf("furnace: expected %.6f %.6f %.6f, mean %.6f %.6f %.6f, stderr %.2e %.2e %.2e\n",
              expected.x, expected.y, expected.z, s.mean.x, s.mean.y, s.mean.z, s.standard_error.x,
              s.standard_error.y, s.standard_error.z);
}

}  // namespace
}  // namespace bakegi
