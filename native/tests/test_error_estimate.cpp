// A bake's estimate of its own error (bake/error_estimate.h), where the truth is known.
//
// Inside a closed diffuse sphere of radius R and albedo rho, the form factor from any point to
// any patch dA of the sphere is dA / (4 pi R^2), whatever the two places. So light reflected
// once irradiates every point alike: E_1 = rho * (total direct flux) / A, and with a lamp of
// intensity I anywhere inside, all its 4 pi I watts land on the wall. Every later bounce
// multiplies by rho, so the indirect value E_ind / pi = rho / (1 - rho) * 4 pi I / (A pi) is
// the same at every point even with the lamp off centre, while the path tracer's samples
// are noisy there (the first reflection sees direct light varying as cos / d^2): a known
// truth under noisy probes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bake/error_estimate.h"
#include "light_transport_fixtures.h"
#include "util/error.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

constexpr float kRadius = 1.5f;

struct SphereCase {
  SceneDescription description;
  glm::dvec3 truth;  // the bake value at every point
};

SphereCase off_centre_lamp_sphere() {
  SphereCase c;
  const glm::vec3 albedo(0.5f, 0.6f, 0.4f);
  const glm::vec3 intensity(3.0f, 2.5f, 2.0f);
  const uint32_t wall = test::add_material(c.description, albedo);
  c.description.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), kRadius, 4, wall));
  // Off centre: direct light on the wall ranges over a factor of about 10.
  c.description.lights.push_back(test::point_light(glm::vec3(0.7f, 0.3f, -0.2f), intensity));
  const double area = test::mesh_area(c.description.meshes[0]);
  const glm::dvec3 rho(albedo);
  c.truth = rho / (1.0 - rho) * glm::dvec3(intensity) * (4.0 * M_PI / area) / M_PI;
  return c;
}

BakePoints points_on(const Mesh& sphere, int count) {
  std::vector<glm::vec3> positions, normals;
  Pcg32 rng(777, 31);
  const size_t triangles = sphere.indices.size() / 3;
  for (int i = 0; i < count; ++i) {
    const size_t t = std::min(size_t(rng.next_float() * float(triangles)), triangles - 1);
    const glm::vec3 a = sphere.positions[sphere.indices[3 * t]];
    const glm::vec3 b = sphere.positions[sphere.indices[3 * t + 1]];
    const glm::vec3 c = sphere.positions[sphere.indices[3 * t + 2]];
    const glm::vec2 bary = sample_triangle_barycentrics(rng.next_float(), rng.next_float());
    positions.push_back(a * (1.0f - bary.x - bary.y) + b * bary.x + c * bary.y);
    normals.push_back(-glm::normalize(glm::cross(b - a, c - a)));
  }
  return test::make_points(positions, normals);
}

double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// The NRMSE of `values` against the uniform truth (the project's metric).
double true_nrmse(const std::vector<glm::vec3>& values, const glm::dvec3& truth) {
  double squared = 0.0;
  for (const glm::vec3& v : values) {
    const double d = luminance(glm::dvec3(v)) - luminance(truth);
    squared += d * d;
  }
  return std::sqrt(squared / double(values.size())) / luminance(truth);
}

class ErrorEstimateInSphere : public testing::Test {
 protected:
  ErrorEstimateInSphere()
      : sphere_(off_centre_lamp_sphere()),
        baker_(sphere_.description),
        points_(points_on(sphere_.description.meshes[0], 256)) {}

  ErrorEstimate estimate(const std::vector<glm::vec3>& baked, int64_t samples,
                         const ErrorProbes& display = {}) {
    ErrorEstimateSettings settings;
    settings.samples = samples;
    JobContext context;
    return estimate_error(baker_.direct(), probes_at_bake_points(points_, points_.size(), 0),
                          display, baked, settings, context);
  }

  std::vector<glm::vec3> truth_everywhere() const {
    return std::vector<glm::vec3>(points_.size(), glm::vec3(sphere_.truth));
  }

  SphereCase sphere_;
  test::Baker baker_;
  BakePoints points_;
};

TEST_F(ErrorEstimateInSphere, RecoversAKnownErrorUnderNoisyProbes) {
  // Baked = truth x (1 +- 10%): the NRMSE is exactly 10%.
  std::vector<glm::vec3> baked = truth_everywhere();
  for (size_t i = 0; i < baked.size(); ++i) baked[i] *= (i % 2 == 0) ? 1.1f : 0.9f;
  ASSERT_NEAR(true_nrmse(baked, sphere_.truth), 0.1, 1e-6);
  const ErrorEstimate e = estimate(baked, 64);
  std::printf("known 10%%: estimated %.4f [%.4f, %.4f], probe noise %.4f, %llu rays\n",
              e.at_points.nrmse, e.at_points.low, e.at_points.high, e.at_points.probe_noise,
              (unsigned long long)e.rays);
  // The probes are noisy (64 paths each): without removing their variance the estimate would
  // be sqrt(0.1^2 + noise^2), far off. Measured noise about 10%.
  EXPECT_GT(e.at_points.probe_noise, 0.05);
  // The estimate's own spread over 256 probes is about 10% of itself here (its bootstrap
  // interval says so); 20% is two of those.
  EXPECT_NEAR(e.at_points.nrmse, 0.1, 0.02);
  EXPECT_LE(e.at_points.low, 0.1);
  EXPECT_GE(e.at_points.high, 0.1);
  EXPECT_EQ(e.at_points.probes, points_.size());
  EXPECT_NEAR(e.at_points.mean_reference, luminance(sphere_.truth), 0.02 * luminance(sphere_.truth));
}

TEST_F(ErrorEstimateInSphere, AnExactBakeEstimatesNearZero) {
  const ErrorEstimate e = estimate(truth_everywhere(), 64);
  std::printf("exact: estimated %.4f [%.4f, %.4f], probe noise %.4f\n", e.at_points.nrmse,
              e.at_points.low, e.at_points.high, e.at_points.probe_noise);
  // Removing the probes' variance leaves only its sampling error: a few percent at most.
  EXPECT_LT(e.at_points.nrmse, 0.03);
  EXPECT_LT(e.at_points.high, 0.05);
}

TEST_F(ErrorEstimateInSphere, APathTracedBakeEstimatesItsOwnNoise) {
  // The bake and the probes use different random streams, so the bake's noise is error.
  test::BakeOptions options;
  options.samples = 16;
  const std::vector<glm::vec3> baked = baker_.bake(points_, options);
  const double truth = true_nrmse(baked, sphere_.truth);
  const ErrorEstimate e = estimate(baked, 256);
  std::printf("path traced, 16 samples: true %.4f, estimated %.4f [%.4f, %.4f]\n", truth,
              e.at_points.nrmse, e.at_points.low, e.at_points.high);
  EXPECT_GT(truth, 0.05);  // a noisy bake, or the check would say nothing
  EXPECT_NEAR(e.at_points.nrmse / truth, 1.0, 0.2);
}

TEST_F(ErrorEstimateInSphere, DisplayProbesSeeTheInterpolatedValue) {
  // Bake points alternately 30% high and low; a display probe halfway between each pair
  // (placed at the first point, weights 1/2, 1/2) shows their mean, which is exact.
  std::vector<glm::vec3> baked = truth_everywhere();
  for (size_t i = 0; i < baked.size(); ++i) baked[i] *= (i % 2 == 0) ? 1.3f : 0.7f;
  ErrorProbes display;
  for (uint32_t i = 0; i + 1 < points_.size(); i += 2) {
    display.add(points_.positions[i], points_.normals[i], 5, {i, i + 1, 0, 0},
                {0.5f, 0.5f, 0.0f, 0.0f});
  }
  check_error_probes(display, points_.size());
  const ErrorEstimate e = estimate(baked, 64, display);
  std::printf("display: at points %.4f, display %.4f\n", e.at_points.nrmse, e.display.nrmse);
  EXPECT_NEAR(e.at_points.nrmse, 0.3, 0.05);
  EXPECT_LT(e.display.nrmse, 0.04);
  EXPECT_EQ(e.display.probes, points_.size() / 2);
  // Per object: every display probe was given object 5, the bake points object 0.
  ASSERT_EQ(e.objects.size(), 2u);
  EXPECT_EQ(e.objects[0].object_id, 0u);
  EXPECT_EQ(e.objects[0].display.probes, 0u);
  EXPECT_EQ(e.objects[1].object_id, 5u);
  EXPECT_EQ(e.objects[1].display.probes, points_.size() / 2);
}

TEST(ErrorProbes, DrawnAtBakePointsAreDistinctAndDeterministic) {
  BakePoints points;
  for (int i = 0; i < 1000; ++i) {
    points.positions.push_back(glm::vec3(float(i), 0.0f, 0.0f));
    points.normals.push_back(glm::vec3(0, 0, 1));
    points.object_ids.push_back(uint32_t(i % 7));
  }
  const ErrorProbes a = probes_at_bake_points(points, 100, 3);
  const ErrorProbes b = probes_at_bake_points(points, 100, 3);
  const ErrorProbes c = probes_at_bake_points(points, 100, 4);
  ASSERT_EQ(a.size(), 100u);
  EXPECT_EQ(a.stencil_points, b.stencil_points);
  EXPECT_NE(a.stencil_points, c.stencil_points);
  for (size_t i = 0; i < a.size(); ++i) {
    const uint32_t p = a.stencil_points[i][0];
    EXPECT_EQ(a.points.positions[i], points.positions[p]);
    EXPECT_EQ(a.points.object_ids[i], points.object_ids[p]);
    EXPECT_EQ(a.stencil_weights[i][0], 1.0f);
    if (i > 0) EXPECT_LT(a.stencil_points[i - 1][0], p);  // distinct (and sorted)
  }
  EXPECT_EQ(probes_at_bake_points(points, 5000, 0).size(), points.size());
}

// Probes drawn half by the bake's light: a few bright points that carry much of the light
// (and so, for a method whose error follows the light, of the error) are met by a few
// hundred probes, and the sampling weights make weighted means over the probes estimate
// means over all points.
TEST(ErrorProbes, DrawnByLightMeetRareBrightPointsAndWeighBackToThePointsMeans) {
  constexpr int kPoints = 20000, kBright = 50;
  BakePoints points;
  std::vector<glm::vec3> baked;
  double total = 0.0;
  for (int i = 0; i < kPoints; ++i) {
    points.positions.push_back(glm::vec3(float(i), 0.0f, 0.0f));
    points.normals.push_back(glm::vec3(0, 0, 1));
    points.object_ids.push_back(0);
    const float y = i % (kPoints / kBright) == 0 ? 40.0f : 1.0f;  // luminance y (grey)
    baked.push_back(glm::vec3(y));
    total += y;
  }
  const double mean = total / kPoints;
  const ErrorProbes a = probes_weighted_by_light(points, baked, 256, 3);
  const ErrorProbes b = probes_weighted_by_light(points, baked, 256, 3);
  ASSERT_EQ(a.size(), 256u);
  ASSERT_EQ(a.sampling_weights.size(), 256u);
  EXPECT_EQ(a.stencil_points, b.stencil_points);
  // Bright points hold 2,000 of the 21,950 units of light: drawn with probability
  // 0.5 x 50 / 20,000 + 0.5 x 0.091 = 0.047 each time (12 of 256 expected; 0.64 uniformly).
  size_t bright = 0;
  double weights = 0.0, weighted_light = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const uint32_t p = a.stencil_points[i][0];
    EXPECT_EQ(a.points.positions[i], points.positions[p]);
    const double y = baked[p].x;
    bright += y > 1.0 ? 1 : 0;
    EXPECT_NEAR(a.sampling_weight(i), 1.0 / (kPoints * (0.5 / kPoints + 0.5 * y / total)), 1e-6);
    weights += a.sampling_weight(i);
    weighted_light += a.sampling_weight(i) * y;
  }
  EXPECT_GE(bright, 5u);
  // The weighted mean of the bake's light over the probes is the points' mean (this is the
  // estimator's denominator and squared-error mean in miniature).
  EXPECT_NEAR(weighted_light / weights, mean, 0.05 * mean);

  // At most `count` points: every point once, uniformly; a black bake: uniformly.
  EXPECT_EQ(probes_weighted_by_light(points, baked, kPoints, 0).size(), size_t(kPoints));
  const std::vector<glm::vec3> black(kPoints, glm::vec3(0.0f));
  const ErrorProbes uniform = probes_weighted_by_light(points, black, 100, 0);
  ASSERT_EQ(uniform.size(), 100u);
  for (size_t i = 0; i < uniform.size(); ++i) EXPECT_EQ(uniform.sampling_weight(i), 1.0f);
}

TEST(ErrorProbes, BadDisplayProbesAreRefused) {
  auto one = [](glm::vec3 p, glm::vec3 n, uint32_t index, float w0, float w1) {
    ErrorProbes probes;
    probes.add(p, n, 0, {index, 1, 0, 0}, {w0, w1, 0.0f, 0.0f});
    return probes;
  };
  auto refused = [](ErrorProbes probes, const std::string& words) {
    try {
      check_error_probes(probes, 4);
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_INVALID_ARGUMENT);
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted; expected: " << words;
  };
  const glm::vec3 up(0, 0, 1);
  refused(one({0, 0, NAN}, up, 0, 1, 0), "display probe 0: position");
  refused(one({1e20f, 0, 0}, up, 0, 1, 0), "out of range");
  refused(one({0, 0, 0}, {0, 0, 0}, 0, 1, 0), "normal is zero");
  refused(one({0, 0, 0}, up, 9, 1, 0), "bake point 9 is out of range (4 bake points)");
  refused(one({0, 0, 0}, up, 0, -1, 2), "negative");
  refused(one({0, 0, 0}, up, 0, 0, 0), "weights sum to 0");
  ErrorProbes fine = one({0, 0, 0}, {0, 0, 5}, 9, 0.0f, 1.0f);  // index 9 weighs nothing
  check_error_probes(fine, 4);
  EXPECT_EQ(fine.points.normals[0], up);
}

}  // namespace
}  // namespace bakegi
