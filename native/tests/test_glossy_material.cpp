// The glossy lobe of materials: validation at the C API, the modified Phong lobe's albedo,
// and the path tracer as the reference for glossy scenes (a closed sphere against a
// quadrature solution of its transport, determinism).
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "api/handles.h"
#include "capi_test_scene.h"
#include "light_transport_fixtures.h"
#include "scene/phong_lobe.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

TEST(GlossyMaterial, ValidationNamesTheMaterial) {
  test::ScenePtr scene = test::new_scene();
  bakegi_material_desc m = test::grey_material(0.5f);
  m.glossy[0] = m.glossy[1] = m.glossy[2] = 0.5f;
  m.glossy_exponent = 1000.0f;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_OK) << bakegi_last_error();
  m.glossy[1] = 0.6f;  // 0.5 + 0.6 > 1 in green
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_SCENE);
  EXPECT_NE(std::string(bakegi_last_error()).find("material 1: albedo + glossy"), std::string::npos)
      << bakegi_last_error();
  m.glossy[1] = 0.5f;
  for (const float bad : {-1.0f, std::nanf(""), INFINITY, 2e6f}) {
    m.glossy_exponent = bad;
    EXPECT_EQ(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_SCENE);
    EXPECT_NE(std::string(bakegi_last_error()).find("material 1: glossy exponent"),
              std::string::npos)
        << bakegi_last_error();
  }
  m.glossy_exponent = 10.0f;
  m.glossy[2] = -0.1f;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_SCENE);
  // A zero-initialized glossy part is a diffuse material, as before the lobe existed.
  bakegi_material_desc diffuse{};
  diffuse.albedo[0] = diffuse.albedo[1] = diffuse.albedo[2] = 1.0f;
  diffuse.albedo_texture = BAKEGI_NO_TEXTURE;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &diffuse, nullptr), BAKEGI_OK);
  EXPECT_FALSE(scene->description.materials.back().has_glossy());
}

TEST(GlossyMaterial, PhongDirectionalAlbedoIsOneAtNormalIncidenceAndMatchesSampling) {
  for (const double n : {0.0, 5.0, 100.0, 5000.0}) {
    EXPECT_NEAR(phong_directional_albedo(n, 1.0), 1.0, 1e-5) << n;
    double previous = 1.0;
    for (double mu = 0.9; mu > 0.0; mu -= 0.1) {
      const double a = phong_directional_albedo(n, mu);
      EXPECT_LE(a, previous + 1e-9) << n << " " << mu;  // the horizon and cosine only take
      previous = a;
    }
    // Narrow lobes: A(μ) → μ (n + 2) / (n + 1).
    if (n >= 100.0) EXPECT_NEAR(phong_directional_albedo(n, 0.5), 0.5 * (n + 2) / (n + 1), 0.01);
  }
  // Against a Monte Carlo estimate with the lobe's own sampling: A = E[(n+2)/(n+1) ⟨N|ω⟩₊].
  const float n = 10.0f;
  const PhongLobe lobe{n};
  const glm::vec3 normal(0, 0, 1);
  const float mu = 0.4f;
  const glm::vec3 axis(std::sqrt(1 - mu * mu), 0.0f, mu);
  Pcg32 rng(7, 3);
  double sum = 0.0;
  const int count = 400000;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 w = lobe.sample(axis, rng.next_float(), rng.next_float());
    // The sampled density and the lobe value agree: f / pdf = (n + 2) / (n + 1).
    if (i < 100) {
      const float c = glm::dot(axis, w);
      EXPECT_NEAR(lobe.value(c) / lobe.pdf(c), (n + 2) / (n + 1), 1e-4f);
    }
    sum += std::max(0.0f, glm::dot(normal, w)) * (n + 2) / (n + 1);
  }
  // Standard error of 400k samples of a [0, 1.1] variable: < 0.0005.
  EXPECT_NEAR(sum / count, phong_directional_albedo(n, mu), 0.002);
}

// A closed sphere lit by a point light at its centre: radiance leaving a wall point at angle
// θ to its normal arrives at another wall point at the same angle (chords make equal angles
// at both ends), so the transport is a 1D integral equation in μ = cos θ:
//   L(μo) = L1(μo) + ρd/π · 2π∫L(μ)μ dμ + ∫ L(μi) μi K(μo, μi) dμi,
//   K(μo, μi) = ρg (n+2)/(2π) ∫_0^{2π} max(0, μi μo + si so cos φ)^n dφ,
//   L1(μ) = ρd E0/π + ρg (n+2)/(2π) μ^n E0   (light arrives along the normal),
// and the bake value is E_indirect/π = 2∫ L(μ) μ dμ. Solved by Nyström's method on
// Gauss-Legendre nodes (96 nodes, 1024 azimuths; the result moves < 1e-4 relative when either
// is doubled).
double sphere_reference(double rho_d, double rho_g, double n, double e0) {
  constexpr int kNodes = 96, kAzimuths = 1024;
  std::vector<double> x(kNodes), w(kNodes);
  for (int i = 0; i < kNodes; ++i) {  // Legendre roots by Newton, mapped to [0, 1]
    double z = std::cos(std::numbers::pi * (i + 0.75) / (kNodes + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= kNodes; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = kNodes * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    x[size_t(i)] = 0.5 * (z + 1.0);
    w[size_t(i)] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2/((1-z²)P'²) halved for [0,1]
  }
  const double norm = rho_g * (n + 2.0) / (2.0 * std::numbers::pi);
  std::vector<double> kernel(size_t(kNodes) * kNodes);
  for (int o = 0; o < kNodes; ++o) {
    for (int i = 0; i < kNodes; ++i) {
      const double so = std::sqrt(1 - x[size_t(o)] * x[size_t(o)]);
      const double si = std::sqrt(1 - x[size_t(i)] * x[size_t(i)]);
      double sum = 0.0;
      for (int k = 0; k < kAzimuths; ++k) {
        const double c = x[size_t(i)] * x[size_t(o)] +
                         si * so * std::cos(2.0 * std::numbers::pi * (k + 0.5) / kAzimuths);
        if (c > 0.0) sum += std::pow(c, n);
      }
      kernel[size_t(o) * kNodes + size_t(i)] = norm * sum * 2.0 * std::numbers::pi / kAzimuths;
    }
  }
  std::vector<double> first(kNodes), total(kNodes), next(kNodes);
  for (int o = 0; o < kNodes; ++o) {
    first[size_t(o)] = rho_d * e0 / std::numbers::pi + norm * std::pow(x[size_t(o)], n) * e0;
  }
  total = first;
  for (int iteration = 0; iteration < 400; ++iteration) {
    double irradiance = 0.0;
    for (int i = 0; i < kNodes; ++i) {
      irradiance += 2.0 * std::numbers::pi * w[size_t(i)] * x[size_t(i)] * total[size_t(i)];
    }
    for (int o = 0; o < kNodes; ++o) {
      double glossy = 0.0;
      for (int i = 0; i < kNodes; ++i) {
        glossy +=
            w[size_t(i)] * x[size_t(i)] * total[size_t(i)] * kernel[size_t(o) * kNodes + size_t(i)];
      }
      next[size_t(o)] = first[size_t(o)] + rho_d / std::numbers::pi * irradiance + glossy;
    }
    total.swap(next);
  }
  double value = 0.0;
  for (int i = 0; i < kNodes; ++i) value += 2.0 * w[size_t(i)] * x[size_t(i)] * total[size_t(i)];
  return value;
}

struct GlossySphere {
  SceneDescription d;
  double e0 = 0.0;
  BakePoints points;
};

GlossySphere glossy_sphere(float rho_d, float rho_g, float exponent) {
  GlossySphere s;
  const uint32_t wall = test::add_material(s.d, glm::vec3(rho_d));
  s.d.materials[wall].glossy = glm::vec3(rho_g);
  s.d.materials[wall].glossy_exponent = exponent;
  // Inward-facing faces and no corner normals: the glossy lobe follows the face normals.
  s.d.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), 1.5f, 4, wall));
  Mesh& sphere = s.d.meshes.back();
  sphere.corner_normals.clear();
  const float intensity = 3.0f;
  s.d.lights.push_back(test::point_light(glm::vec3(0.0f), glm::vec3(intensity)));
  s.e0 = intensity * 4.0 * std::numbers::pi / test::mesh_area(sphere);
  std::vector<glm::vec3> positions, normals;
  for (size_t t = 0; t < 64; ++t) {  // triangle centroids spread over the sphere
    const size_t tri = (t * 79) % (sphere.indices.size() / 3);
    const glm::vec3 a = sphere.positions[sphere.indices[3 * tri]];
    const glm::vec3 b = sphere.positions[sphere.indices[3 * tri + 1]];
    const glm::vec3 c = sphere.positions[sphere.indices[3 * tri + 2]];
    positions.push_back((a + b + c) / 3.0f);
    normals.push_back(-glm::normalize(glm::cross(b - a, c - a)));
  }
  s.points = test::make_points(positions, normals);
  return s;
}

TEST(GlossyPathTrace, ClosedSphereMatchesTheQuadratureSolution) {
  // ρd + ρg = 0.8; a lobe about 0.3 rad wide, so facets (~0.05 rad apart) barely show.
  const float rho_d = 0.2f, rho_g = 0.6f, n = 20.0f;
  GlossySphere s = glossy_sphere(rho_d, rho_g, n);
  const double expected = sphere_reference(rho_d, rho_g, n, s.e0);
  // Not ρ/(1−ρ) of the total reflectance: the Phong lobe's albedo falls off at grazing.
  const double diffuse_like = (rho_d + rho_g) * s.e0 / (std::numbers::pi * (1 - rho_d - rho_g));
  test::Baker baker(s.d);
  test::BakeOptions options;
  options.samples = 1024;
  const std::vector<glm::vec3> values = baker.bake(s.points, options);
  std::vector<double> channel;
  for (const glm::vec3& v : values) channel.push_back(v.y);
  const double mean = test::mean(channel);
  const double standard_error = test::standard_deviation(channel) / std::sqrt(channel.size());
  std::printf(
      "glossy sphere: quadrature %.5f (total-reflectance series %.5f), path tracer %.5f "
      "(%+.2f%%, standard error %.2f%%)\n",
      expected, diffuse_like, mean, 100 * (mean / expected - 1), 100 * standard_error / expected);
  // Tolerance: 5 standard errors (measured 0.55%) plus 1% for the tessellation (flat facets
  // tilt the lobe and the point light's incidence by up to ~0.03 rad).
  EXPECT_NEAR(mean, expected, (5 * standard_error / expected + 0.01) * expected);
  EXPECT_GT(std::abs(diffuse_like / expected - 1), 0.05);  // the test tells the two apart
  EXPECT_EQ(values[0].x, values[0].y);                     // grey in, grey out
}

TEST(GlossyPathTrace, DeterministicForASeed) {
  GlossySphere s = glossy_sphere(0.1f, 0.85f, 2000.0f);  // a near mirror
  test::Baker baker(s.d);
  test::BakeOptions options;
  options.samples = 16;
  const std::vector<glm::vec3> a = baker.bake(s.points, options);
  const std::vector<glm::vec3> b = baker.bake(s.points, options);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])), 0);
  options.seed = 1;
  const std::vector<glm::vec3> c = baker.bake(s.points, options);
  EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(a[0])), 0);
  for (const glm::vec3& v : a) {
    EXPECT_TRUE(std::isfinite(v.x) && v.x >= 0.0f) << v.x;
  }
}

}  // namespace
}  // namespace bakegi
