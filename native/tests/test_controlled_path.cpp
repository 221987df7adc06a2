// The path tracer with a radiance cache as control variate (solvers/pathtrace/controlled_path.h):
// unbiased whatever the cache says, the residual weighted right, the pilot's choice of q.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "light_transport_fixtures.h"
#include "solvers/pathtrace/controlled_path.h"
#include "solvers/pathtrace/controlled_path_field.h"
#include "solvers/radiance_cache.h"
#include "util/job_context.h"
#include "util/random.h"

namespace bakegi {
namespace {

// An indirect irradiance that is `value` times a factor from 0.2 to 3.2 across each triangle
// (a constant cache would cancel: with stratified decisions exactly q of a point's paths go
// on, so C - (B/q) C sums to 0 over them).
class UnevenCache : public RadianceCache {
 public:
  explicit UnevenCache(glm::vec3 value) : value_(value) {}
  bool irradiance_at(const Hit& hit, const glm::vec3&, CachedIrradiance& out) const override {
    out.indirect_over_pi = value_ * (0.2f + 3.0f * hit.b1);
    return true;
  }
  size_t memory_bytes() const override { return 0; }

 private:
  glm::vec3 value_;
};

// Point light of intensity I at the centre of a closed sphere of albedo rho
// (test_pathtrace_sphere.cpp): E_ind / pi = rho E0 / (pi (1 - rho)) everywhere, E0 the mean
// direct irradiance 4 pi I / A.
TEST(ControlledPath, UnbiasedWithAnyCacheInAClosedSphere) {
  const glm::vec3 albedo(0.3f, 0.5f, 0.7f);
  const glm::vec3 intensity(4.0f, 2.0f, 1.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, albedo);
  d.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), 1.5f, 4, wall));
  d.lights.push_back(test::point_light(glm::vec3(0.0f), intensity));
  const glm::dvec3 direct = glm::dvec3(intensity) * (4.0 * M_PI / test::mesh_area(d.meshes[0]));
  const glm::dvec3 rho(albedo);
  const glm::dvec3 expected = rho * direct / (M_PI * (1.0 - rho));
  test::Baker baker(d);

  // Points on the wall facing the centre.
  std::vector<glm::vec3> positions, normals;
  Pcg32 rng(5, 9);
  for (int i = 0; i < 64; ++i) {
    const float z = 1.0f - 2.0f * rng.next_float(), phi = 2.0f * float(M_PI) * rng.next_float();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const glm::vec3 n(r * std::cos(phi), r * std::sin(phi), z);
    positions.push_back(1.49f * n);
    normals.push_back(-n);
  }
  const BakePoints points = test::make_points(positions, normals);
  PathTraceSettings settings;
  settings.sampling.samples = 1024;
  const glm::vec3 truth(expected);
  // About the truth, none, twice it, the wrong colour.
  for (const glm::vec3 cached : {truth, glm::vec3(0.0f), 2.0f * truth, glm::vec3(truth.z, 0, 0)}) {
    ControlledPathField field(baker.direct(), std::make_shared<UnevenCache>(cached), settings,
                              0.25);
    JobContext context;
    std::vector<glm::vec3> out(points.size());
    field.evaluate(points, out, context);
    for (int c = 0; c < 3; ++c) {
      double sum = 0.0, squares = 0.0;
      for (const glm::vec3& v : out) sum += v[c], squares += double(v[c]) * v[c];
      const double n = double(out.size());
      const double mean = sum / n;
      const double standard_error = std::sqrt((squares / n - mean * mean) / (n - 1.0));
      // The residual with weight 1 instead of 1/q would be 0.75 (C - R) off: with C = 2R
      // at least 40% of the value (R, the light beyond the first bounce, is at least
      // rho of it). 2% is about 3 standard errors of these 64 x 1024 samples with the worst
      // cache (printed: 0.7%) and 10 or more with the others; the seeds are fixed.
      EXPECT_NEAR(mean, expected[c], 0.02 * expected[c])
          << "cache " << cached[c] << ", channel " << c;
      std::printf("cache %.4f channel %d: mean %.5f expected %.5f (standard error %.2f%%)\n",
                  cached[c], c, mean, expected[c], 100.0 * standard_error / expected[c]);
    }
  }
}

TEST(ControlledPath, ResidualStatisticsChooseTheBestProbability) {
  // Two points of the same two samples: S = F + R = 2 and 6, residuals R - C = 1 and -1;
  // 2 rays to the first light sample, 6 after it.
  ControlledSampleParts a, b;
  a.first_light = glm::vec3(1.0f);
  a.rest = glm::vec3(1.0f);
  a.control = glm::vec3(0.0f);
  b.first_light = glm::vec3(3.0f);
  b.rest = glm::vec3(3.0f);
  b.control = glm::vec3(4.0f);
  a.first_rays = b.first_rays = 2;
  a.rest_rays = b.rest_rays = 6;
  const ControlledSampleParts samples[] = {a, b};
  ResidualStatistics statistics;
  statistics.add_point(samples, 2);
  statistics.add_point(samples, 2);
  // S = 2 and 6: mean 4, sample variance 8; residuals 1 and -1: M = 1.
  EXPECT_NEAR(statistics.path_spread(), std::sqrt(8.0) / 4.0, 1e-9);
  EXPECT_NEAR(statistics.residual_spread(), 1.0 / 4.0, 1e-9);
  EXPECT_DOUBLE_EQ(statistics.first_rays(), 2.0);
  EXPECT_DOUBLE_EQ(statistics.rest_rays(), 6.0);
  // q* = sqrt(M c1 / (A c2)), A = 8 - 1.
  EXPECT_NEAR(statistics.best_rest_probability(0.05), std::sqrt(1.0 * 2.0 / (7.0 * 6.0)), 1e-9);
  EXPECT_DOUBLE_EQ(statistics.best_rest_probability(0.5), 0.5);
  // A residual as large as the path: going on always is best.
  ControlledSampleParts bad = a;
  bad.control = glm::vec3(-10.0f);
  const ControlledSampleParts worse[] = {bad, bad};
  ResidualStatistics useless;
  useless.add_point(worse, 2);
  EXPECT_DOUBLE_EQ(useless.best_rest_probability(0.05), 1.0);
}

}  // namespace
}  // namespace bakegi
