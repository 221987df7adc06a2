// The meshless hierarchical basis (Lehtinen et al. 2008, §2.1-2.2, §2.4, §4.1) on hand-made
// point sets: jittered grids on a plane (spacing R/2^l per level, r = C R with C from 1.5
// on the coarsest to 2.5 on the finest level, as in §2.3) and Fibonacci points on a sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <vector>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/multilevel_approximation.h"
#include "solvers/meshless/weight_function.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"

namespace bakegi::meshless {
namespace {

constexpr float kPi = 3.14159265358979f;

float support_scale(uint32_t level, uint32_t levels) {
  return levels > 1 ? 1.5f + 1.0f * float(level) / float(levels - 1) : 2.0f;
}

// Jittered grid on the square [0, extent]^2 of the plane z = 0 (normal +z), `levels` levels
// with spacing coarse_spacing / 2^l, each point moved by up to +-jitter/2 spacings.
std::vector<BasisPoint> plane_points(uint32_t levels, float extent, float coarse_spacing,
                                     float jitter = 0.5f, uint64_t seed = 1) {
  Pcg32 rng(seed, 7);
  std::vector<BasisPoint> points;
  for (uint32_t l = 0; l < levels; ++l) {
    const float h = coarse_spacing / float(1u << l);
    const int cells = int(std::ceil(extent / h));
    for (int i = 0; i < cells; ++i)
      for (int k = 0; k < cells; ++k) {
        BasisPoint p;
        p.position = {(float(i) + 0.5f + jitter * (rng.next_float() - 0.5f)) * h,
                      (float(k) + 0.5f + jitter * (rng.next_float() - 0.5f)) * h, 0.0f};
        p.normal = {0.0f, 0.0f, 1.0f};
        p.radius = support_scale(l, levels) * h;
        p.level = l;
        points.push_back(p);
      }
  }
  return points;
}

// Fibonacci points on the unit sphere, outward normals; level l has 40 * 4^l points.
std::vector<BasisPoint> sphere_points(uint32_t levels) {
  std::vector<BasisPoint> points;
  for (uint32_t l = 0; l < levels; ++l) {
    const int count = 40 << (2 * l);
    // Mean spacing of `count` points on the sphere: sqrt(4 pi / count).
    const float spacing = std::sqrt(4.0f * kPi / float(count));
    for (int i = 0; i < count; ++i) {
      const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(count);
      const float rho = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const float phi = float(i) * 2.39996323f;
      BasisPoint p;
      p.position = {rho * std::cos(phi), rho * std::sin(phi), z};
      p.normal = glm::normalize(p.position);
      p.radius = support_scale(l, levels) * spacing;
      p.level = l;
      points.push_back(p);
    }
  }
  return points;
}

float smooth_function(const glm::vec3& x) {
  return 1.0f + 0.5f * std::sin(2.0f * kPi * x.x) * std::cos(1.5f * kPi * x.y) + 0.3f * x.y;
}

std::vector<float> sample(const BasisHierarchy& basis, float (*f)(const glm::vec3&)) {
  std::vector<float> values(basis.size());
  for (uint32_t j = 0; j < basis.size(); ++j) values[j] = f(basis.point(j).position);
  return values;
}

// Random queries on the plane, inside [margin, 1 - margin]^2 (away from the boundary, where
// one-sided Shepard averages lose accuracy), normal +z.
std::vector<glm::vec3> plane_queries(int count, float margin, uint64_t seed = 3) {
  Pcg32 rng(seed, 11);
  std::vector<glm::vec3> queries(count);
  for (glm::vec3& q : queries)
    q = {margin + (1 - 2 * margin) * rng.next_float(), margin + (1 - 2 * margin) * rng.next_float(),
         0.0f};
  return queries;
}

// F_l: the expansion with every coefficient finer than `level` zeroed (α on levels <= l do
// not depend on finer levels, Eq. 7).
std::vector<float> truncated(const BasisHierarchy& basis, std::vector<float> alpha,
                             uint32_t level) {
  if (level + 1 < basis.level_count())
    std::fill(alpha.begin() + basis.level_begin(level + 1), alpha.end(), 0.0f);
  return alpha;
}

float max_error(const BasisHierarchy& basis, const std::vector<float>& alpha,
                const std::vector<glm::vec3>& queries, float (*f)(const glm::vec3&)) {
  std::vector<glm::vec3> normals(queries.size(), glm::vec3(0, 0, 1));
  std::vector<float> values(queries.size());
  EXPECT_EQ(evaluate_many(basis, alpha, 1, queries, normals, values), 0u);
  float error = 0.0f;
  for (size_t q = 0; q < queries.size(); ++q)
    error = std::max(error, std::abs(values[q] - f(queries[q])));
  return error;
}

TEST(MeshlessBasis, SortsByLevelAndKeepsInputOrder) {
  std::vector<BasisPoint> points = plane_points(3, 1.0f, 0.5f);
  std::reverse(points.begin(), points.end());
  const BasisHierarchy basis(points);
  ASSERT_EQ(basis.size(), points.size());
  ASSERT_EQ(basis.level_count(), 3u);
  EXPECT_EQ(basis.level_begin(0), 0u);
  EXPECT_EQ(basis.level_end(2), basis.size());
  for (uint32_t l = 0; l < 3; ++l)
    for (uint32_t j = basis.level_begin(l); j < basis.level_end(l); ++j) {
      EXPECT_EQ(basis.point(j).level, l);
      EXPECT_EQ(basis.point(j).position, points[basis.input_index(j)].position);
      if (j > basis.level_begin(l)) EXPECT_LT(basis.input_index(j - 1), basis.input_index(j));
    }
  EXPECT_GT(basis.memory_bytes(), basis.size() * sizeof(BasisPoint));
}

// The R-tree query must find exactly the points a brute-force loop finds, with random
// query normals (so the tight, tilted support boxes and the back-facing cut are exercised).
TEST(MeshlessBasis, GatherWeightsMatchesBruteForce) {
  const BasisHierarchy basis(sphere_points(3));
  Pcg32 rng(5, 1);
  std::vector<BasisValue> found;
  for (int q = 0; q < 300; ++q) {
    const glm::vec3 x =
        1.1f *
        glm::vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f) * 2.0f;
    const glm::vec3 n = glm::normalize(
        glm::vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
    for (uint32_t l = 0; l < basis.level_count(); ++l) {
      found.clear();
      basis.gather_weights(l, x, n, found);
      std::vector<std::pair<uint32_t, float>> expected, got;
      for (uint32_t j = basis.level_begin(l); j < basis.level_end(l); ++j) {
        const float w = weight(basis.point(j), x, n);
        if (w > 0.0f) expected.push_back({j, w});
      }
      for (const BasisValue& v : found) got.push_back({v.index, v.value});
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, expected);
    }
  }
}

// Eq. 2: within a level, the basis functions sum to 1 wherever the weight sum is > 0, and
// a back-facing query gets no weight at all (max(0, n . n_j)^2 = 0).
TEST(MeshlessBasis, PartitionOfUnityAndBackFacingNormals) {
  const BasisHierarchy plane(plane_points(3, 1.0f, 0.25f));
  Pcg32 rng(9, 2);
  std::vector<BasisValue> values;
  int covered = 0;
  for (int q = 0; q < 400; ++q) {
    // Also outside the square and slightly off the plane, where coverage ends.
    const glm::vec3 x(1.4f * rng.next_float() - 0.2f, 1.4f * rng.next_float() - 0.2f,
                      0.1f * (rng.next_float() - 0.5f));
    const glm::vec3 n =
        glm::normalize(glm::vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1.0f));
    for (uint32_t l = 0; l < plane.level_count(); ++l) {
      values.clear();
      const float sum = plane.gather_basis(l, x, n, values);
      if (sum > 0.0f) {
        ++covered;
        float total = 0.0f;
        for (const BasisValue& v : values) total += v.value;
        // ~30 terms each rounded once to float: 30 * 6e-8, far below 1e-5.
        EXPECT_NEAR(total, 1.0f, 1e-5f);
      } else {
        EXPECT_TRUE(values.empty());
      }
      values.clear();
      plane.gather_weights(l, x, -n, values);
      EXPECT_TRUE(values.empty()) << "back-facing query got weight";
      EXPECT_EQ(plane.gather_basis(l, x, -n, values), 0.0f);
      EXPECT_TRUE(values.empty());
    }
  }
  EXPECT_GT(covered, 600);  // most of the 1200 (query, level) pairs lie inside the square
  // A normal at 90 degrees or more from +z gets nothing either.
  values.clear();
  plane.gather_weights(1, {0.5f, 0.5f, 0.0f}, {1.0f, 0.0f, 0.0f}, values);
  EXPECT_TRUE(values.empty());
}

// §2.1's DAG against its definitions, brute force, on the sphere (normals differ between
// points, so w is not symmetric) and the plane (equal normals and radii per level, so the
// neighbor relation is symmetric there).
TEST(MeshlessBasis, DagMatchesDefinitions) {
  const BasisHierarchy basis(sphere_points(3));
  std::vector<BasisValue> values;
  size_t asymmetric_neighbors = 0;
  for (uint32_t j = 0; j < basis.size(); ++j) {
    const BasisPoint& p = basis.point(j);
    std::vector<uint32_t> neighbors, children, parents;
    for (uint32_t m = 0; m < basis.size(); ++m) {
      const BasisPoint& q = basis.point(m);
      // B_j(p_m) != 0 exactly when w_j(p_m) > 0 (the normalizing sum includes w_j).
      if (q.level == p.level && m != j && weight(p, q.position, q.normal) > 0.0f)
        neighbors.push_back(m);
      if (q.level == p.level + 1 && weight(p, q.position, q.normal) > 0.0f) children.push_back(m);
      if (q.level + 1 == p.level && weight(q, p.position, p.normal) > 0.0f) parents.push_back(m);
    }
    const auto span_vector = [](std::span<const uint32_t> s) {
      return std::vector<uint32_t>(s.begin(), s.end());
    };
    EXPECT_EQ(span_vector(basis.neighbors(j)), neighbors);
    EXPECT_EQ(span_vector(basis.children(j)), children);
    EXPECT_EQ(span_vector(basis.parents(j)), parents);
    for (uint32_t k : basis.parents(j)) {
      const auto c = basis.children(k);
      EXPECT_TRUE(std::find(c.begin(), c.end(), j) != c.end());
    }
    for (uint32_t m : basis.neighbors(j)) {
      const auto back = basis.neighbors(m);
      const bool mutual = std::find(back.begin(), back.end(), j) != back.end();
      // Symmetric exactly where both weights are non-zero.
      EXPECT_EQ(mutual, weight(basis.point(m), p.position, p.normal) > 0.0f);
      if (!mutual) ++asymmetric_neighbors;
    }
    // coarser_basis(j): B_k(p_j) with j's own normal, every coarser level normalized alone.
    std::vector<BasisValue> expected;
    for (uint32_t l = 0; l < p.level; ++l) basis.gather_basis(l, p.position, p.normal, expected);
    const auto coarser = basis.coarser_basis(j);
    ASSERT_EQ(coarser.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(coarser[i].index, expected[i].index);
      EXPECT_FLOAT_EQ(coarser[i].value, expected[i].value);
    }
  }
  // Different normals make w_j(p_m) != w_m(p_j): the sphere does have one-sided pairs.
  EXPECT_GT(asymmetric_neighbors, 0u);

  const BasisHierarchy plane(plane_points(3, 1.0f, 0.25f));
  for (uint32_t j = 0; j < plane.size(); ++j)
    for (uint32_t m : plane.neighbors(j)) {
      const auto back = plane.neighbors(m);
      EXPECT_TRUE(std::find(back.begin(), back.end(), j) != back.end());
    }
}

TEST(MeshlessBasis, InvalidInputThrows) {
  const auto expect_invalid = [](auto&& call) {
    try {
      call();
      ADD_FAILURE() << "no exception";
    } catch (const Error& error) {
      EXPECT_EQ(error.status(), BAKEGI_ERROR_INVALID_ARGUMENT);
    }
  };
  std::vector<BasisPoint> good = plane_points(2, 1.0f, 0.5f);
  expect_invalid([] { BasisHierarchy(std::vector<BasisPoint>{}); });
  auto gap = good;
  for (BasisPoint& p : gap)
    if (p.level == 1) p.level = 2;
  expect_invalid([&] { BasisHierarchy{gap}; });
  auto no_zero = good;
  for (BasisPoint& p : no_zero) p.level += 1;
  expect_invalid([&] { BasisHierarchy{no_zero}; });
  auto radius = good;
  radius[3].radius = 0.0f;
  expect_invalid([&] { BasisHierarchy{radius}; });
  auto normal = good;
  normal[2].normal = {0.0f, 0.0f, 2.0f};
  expect_invalid([&] { BasisHierarchy{normal}; });
  auto position = good;
  position[1].position.x = std::nanf("");
  expect_invalid([&] { BasisHierarchy{position}; });

  const BasisHierarchy basis(good);
  std::vector<float> short_samples(basis.size() - 1);
  expect_invalid([&] { project_samples(basis, short_samples, 1); });
  std::vector<float> samples(basis.size());
  expect_invalid([&] { pull_push_project(basis, samples, 0); });
  std::vector<glm::vec3> positions(4), normals(3, glm::vec3(0, 0, 1));
  std::vector<float> out(4);
  expect_invalid([&] { evaluate_many(basis, samples, 1, positions, normals, out); });
}

TEST(MeshlessBasis, CancelledJobStopsTheBuild) {
  JobContext job;
  job.cancel();
  try {
    BasisHierarchy basis(plane_points(2, 1.0f, 0.5f), &job);
    ADD_FAILURE() << "no exception";
  } catch (const Error& error) {
    EXPECT_EQ(error.status(), BAKEGI_ERROR_CANCELLED);
  }
}

// Eqs. 4-7: adding levels refines F_l towards a smooth f, and the finest level is accurate.
TEST(MeshlessBasis, MultilevelApproximationConverges) {
  const BasisHierarchy basis(plane_points(5, 1.0f, 0.25f));  // spacing 0.25 .. 1/64
  const std::vector<float> alpha = project_samples(basis, sample(basis, smooth_function), 1);
  // Margin 0.25 (2/3 of the coarsest radius 0.375): the error is measured where the
  // supports are mostly two-sided; Shepard is only first-order at a boundary.
  const std::vector<glm::vec3> queries = plane_queries(500, 0.25f);
  std::vector<float> errors;
  for (uint32_t l = 0; l < basis.level_count(); ++l)
    errors.push_back(max_error(basis, truncated(basis, alpha, l), queries, smooth_function));
  // Measured max errors 0.234, 0.064, 0.016, 0.0039, 0.0009 (a function of range ~1.3):
  // each level divides the error by ~4, the O(h^2) of a symmetric Shepard average on
  // quasi-uniform points; require at least 2.5x per level and 2e-3 (2x the measured value)
  // at the finest.
  for (size_t l = 1; l < errors.size(); ++l)
    EXPECT_LT(errors[l], errors[l - 1] / 2.5f) << "level " << l;
  EXPECT_LT(errors.back(), 2e-3f);
  EXPECT_GT(errors.front(), 10.0f * errors.back());
}

// P and P† on a constant: both reproduce it exactly where every level covers, the coarse
// coefficients carry it and every finer coefficient is 0 (up to float rounding of a
// partition of unity, ~1e-6 per level).
TEST(MeshlessBasis, ConstantIsReproducedByBothProjections) {
  const BasisHierarchy basis(plane_points(4, 1.0f, 0.25f));
  const std::vector<float> constant(basis.size(), 2.5f);
  for (const auto& alpha :
       {project_samples(basis, constant, 1), pull_push_project(basis, constant, 1)}) {
    for (uint32_t j = 0; j < basis.level_end(0); ++j) EXPECT_FLOAT_EQ(alpha[j], 2.5f);
    for (uint32_t j = basis.level_end(0); j < basis.size(); ++j) EXPECT_NEAR(alpha[j], 0.0f, 1e-5f);
    EXPECT_LT(
        max_error(basis, alpha, plane_queries(200, 0.0f), [](const glm::vec3&) { return 2.5f; }),
        1e-5f);
  }
}

float wave(const glm::vec3& x) {
  return std::sin(2.0f * kPi * x.x / 0.75f);
}
float ramp(const glm::vec3& x) {
  return 2.0f * x.x - x.y;
}

// The w_i-weighted mean of `values` over the points of `level` (brute force).
double kernel_mean(const BasisHierarchy& basis, const BasisPoint& center, uint32_t level,
                   const std::vector<float>& values) {
  double sum = 0.0, weight_sum = 0.0;
  for (uint32_t m = basis.level_begin(level); m < basis.level_end(level); ++m) {
    const float w = weight(center, basis.point(m).position, basis.point(m).normal);
    sum += w * values[m];
    weight_sum += w;
  }
  return sum / weight_sum;
}

// P† (§2.1 "Pull-Push Approximation"): coefficients carry local means of f, not samples.
TEST(MeshlessBasis, PullPushCarriesLocalMeans) {
  const BasisHierarchy basis(plane_points(4, 2.0f, 0.25f));
  const uint32_t finest = basis.level_count() - 1;
  const auto interior = [](const BasisPoint& c) {
    return std::min({c.position.x, c.position.y, 2 - c.position.x, 2 - c.position.y}) >= c.radius;
  };
  // The second-finest level is exactly the w_i-weighted mean of the finest samples (its
  // children are every finest point with w_i > 0); double sums, float results: 1e-6.
  const std::vector<float> samples = sample(basis, wave);
  const std::vector<float> averages = pull_averages(basis, samples, 1);
  for (uint32_t i = basis.level_begin(finest - 1); i < basis.level_end(finest - 1); ++i)
    EXPECT_NEAR(averages[i], kernel_mean(basis, basis.point(i), finest, samples), 1e-6);

  // Coarse level, a wave of wavelength 0.75 against coarse radius 0.375: P keeps the point
  // sample; the mean under w_0 is attenuated (measured ~0.53 of the sample near crests), and
  // the pull, which composes w_0 * w_1 * w_2 (variance ~1.5x that of w_0 with these radii),
  // attenuates further (~0.41 of the sample, ~0.53^1.5 as a Gaussian model predicts).
  // Bounds: mean below 0.7 of the sample; P† between half the mean and the mean (+5e-3 for
  // float rounding and jitter asymmetry).
  const std::vector<float> p = project_samples(basis, samples, 1);
  const std::vector<float> pp = pull_push_project(basis, samples, 1);
  int checked = 0;
  for (uint32_t i = 0; i < basis.level_end(0); ++i) {
    const BasisPoint& c = basis.point(i);
    // Near the wave's crests, where its slope (up to 8.4) times the jitter asymmetry (see
    // the linear case below, ~0.03) cannot blur the comparison.
    if (!interior(c) || std::abs(samples[i]) < 0.9f) continue;
    const double mean = kernel_mean(basis, c, finest, samples);
    EXPECT_FLOAT_EQ(p[i], samples[i]);
    EXPECT_GT(pp[i] * samples[i], 0.0f);
    EXPECT_GT(mean * samples[i], 0.0);
    EXPECT_LT(std::abs(pp[i]), std::abs(mean) + 5e-3);
    EXPECT_LT(std::abs(mean), 0.7 * std::abs(samples[i]));
    EXPECT_GT(std::abs(pp[i]), 0.5 * std::abs(mean));
    ++checked;
  }
  EXPECT_GT(checked, 5);

  // A linear function: every symmetric average reproduces it, so P† coarse coefficients
  // equal f(x_i) up to the jittered points' asymmetry. Measured max 0.03 for a slope of
  // ~2.2 over a support of radius 0.375; 0.06 allows seed variation.
  const std::vector<float> linear = sample(basis, ramp);
  const std::vector<float> pp_linear = pull_push_project(basis, linear, 1);
  float linear_gap = 0.0f;
  for (uint32_t i = 0; i < basis.level_end(0); ++i)
    if (interior(basis.point(i)))
      linear_gap = std::max(linear_gap, std::abs(pp_linear[i] - linear[i]));
  EXPECT_LT(linear_gap, 0.06f);
}

// Both projections reach the function at the finest level; they distribute it differently.
// P† coarse levels carry smoothed means, so the finer levels must restore the detail the
// smoothing removed: on a smooth function P†'s fine coefficients are small but LARGER than
// P's (measured rms at the finest level 0.0116 vs 0.0041; P's residual is only the
// interpolation error of F_{L-1}, P†'s adds the smoothing bias of the pulled means).
TEST(MeshlessBasis, PullPushConvergesAtFinestLevel) {
  const BasisHierarchy basis(plane_points(5, 1.0f, 0.25f));
  const std::vector<float> samples = sample(basis, smooth_function);
  const std::vector<float> p = project_samples(basis, samples, 1);
  const std::vector<float> pp = pull_push_project(basis, samples, 1);
  const std::vector<glm::vec3> queries = plane_queries(300, 0.25f);
  // Measured 0.0009 (P) and 0.0015 (P†); 2x margins.
  EXPECT_LT(max_error(basis, p, queries, smooth_function), 2e-3f);
  EXPECT_LT(max_error(basis, pp, queries, smooth_function), 3e-3f);
  const auto rms = [&](const std::vector<float>& alpha, uint32_t level) {
    double sum = 0.0;
    for (uint32_t j = basis.level_begin(level); j < basis.level_end(level); ++j)
      sum += double(alpha[j]) * alpha[j];
    return std::sqrt(sum / double(basis.level_end(level) - basis.level_begin(level)));
  };
  // Detail coefficients shrink level by level for both (measured rms P: 0.108, 0.045, 0.013,
  // 0.004; P†: 0.100, 0.065, 0.028, 0.012).
  for (uint32_t l = 2; l < basis.level_count(); ++l) {
    EXPECT_LT(rms(p, l), 0.7 * rms(p, l - 1)) << "level " << l;
    EXPECT_LT(rms(pp, l), 0.7 * rms(pp, l - 1)) << "level " << l;
  }
  const uint32_t finest = basis.level_count() - 1;
  EXPECT_LT(rms(pp, finest), 0.02);
  EXPECT_GT(rms(pp, finest), 1.5 * rms(p, finest));
}

// Channels are independent: a 3-channel projection equals three scalar ones, and
// evaluate_many equals evaluate query by query.
TEST(MeshlessBasis, ChannelsAndBatchEvaluationAgree) {
  const BasisHierarchy basis(sphere_points(3));
  const uint32_t channels = 3;
  std::vector<float> rgb(basis.size() * channels);
  std::vector<std::vector<float>> scalar(channels, std::vector<float>(basis.size()));
  for (uint32_t j = 0; j < basis.size(); ++j)
    for (uint32_t c = 0; c < channels; ++c) {
      const glm::vec3 x = basis.point(j).position;
      rgb[j * channels + c] = scalar[c][j] = std::sin(3.0f * x[c]) + float(c);
    }
  const std::vector<float> alpha = pull_push_project(basis, rgb, channels);
  for (uint32_t c = 0; c < channels; ++c) {
    const std::vector<float> a = pull_push_project(basis, scalar[c], 1);
    for (uint32_t j = 0; j < basis.size(); ++j) EXPECT_EQ(alpha[j * channels + c], a[j]);
  }
  std::vector<glm::vec3> positions, normals;
  Pcg32 rng(4, 4);
  for (int q = 0; q < 1000; ++q) {
    const glm::vec3 n = glm::normalize(
        glm::vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
    positions.push_back(n);
    normals.push_back(n);
  }
  std::vector<float> batch(positions.size() * channels), single(channels);
  EXPECT_EQ(evaluate_many(basis, alpha, channels, positions, normals, batch), 0u);
  std::vector<BasisValue> scratch;
  for (size_t q = 0; q < positions.size(); ++q) {
    ASSERT_TRUE(evaluate(basis, alpha, channels, positions[q], normals[q], single, scratch));
    for (uint32_t c = 0; c < channels; ++c) EXPECT_EQ(batch[q * channels + c], single[c]);
  }
}

// §4.1: the flattened single-level basis reproduces the hierarchical evaluation at bake
// points with one query. Accuracy against f and against F_L for each choice of points.
TEST(MeshlessBasis, FlatteningMatchesHierarchicalEvaluation) {
  const BasisHierarchy basis(plane_points(5, 1.0f, 0.25f));
  const std::vector<float> alpha = project_samples(basis, sample(basis, smooth_function), 1);
  const std::vector<glm::vec3> queries = plane_queries(500, 0.25f);
  const std::vector<glm::vec3> normals(queries.size(), glm::vec3(0, 0, 1));
  std::vector<float> hierarchical(queries.size());
  evaluate_many(basis, alpha, 1, queries, normals, hierarchical);
  float results[3][2];
  for (FlatPoints choice : {FlatPoints::kFinestLevel, FlatPoints::kAllPointsFinestRadius,
                            FlatPoints::kAllPointsOwnRadius})
    for (uint32_t passes : {0u, 1u}) {  // 2 passes: measured in the comments below
      const FlatExpansion flat = flatten(basis, alpha, 1, choice, passes);
      ASSERT_EQ(flat.basis.level_count(), 1u);
      std::vector<float> values(queries.size());
      EXPECT_EQ(evaluate_many(flat.basis, flat.coefficients, 1, queries, normals, values), 0u);
      float to_hierarchy = 0.0f, to_function = 0.0f;
      for (size_t q = 0; q < queries.size(); ++q) {
        to_hierarchy = std::max(to_hierarchy, std::abs(values[q] - hierarchical[q]));
        to_function = std::max(to_function, std::abs(values[q] - smooth_function(queries[q])));
      }
      if (choice == FlatPoints::kFinestLevel) {
        EXPECT_EQ(flat.basis.size(), basis.level_end(4) - basis.level_begin(4));
        // Measured max |flat - f|: 0.0066 (no pass), 0.0045 (1), 0.0039 (2), against 0.0009
        // for the hierarchy: one Shepard level smooths F_L by O(r^2 ∇²F); 1.5x margins.
        EXPECT_LT(to_function, passes == 0 ? 0.010f : 0.0068f);
      } else {
        EXPECT_EQ(flat.basis.size(), basis.size());
      }
      results[int(choice)][passes] = to_hierarchy;
    }
  // Measured max |flat - F_L| (passes 0 / 1 / 2): finest level 0.0067 / 0.0041 / 0.0037;
  // all points, finest radius 0.0084 / 0.0070 / 0.0062; all points, own radius
  // 0.042 / 0.0080 / 0.0042. The default (finest level, one pass) is the best at one pass.
  EXPECT_LT(results[0][1], results[1][1]);
  EXPECT_LT(results[0][1], results[2][1]);
  EXPECT_LT(results[0][1], results[0][0]);
  EXPECT_LT(results[0][0], results[2][0]);
}

// The default flat level keeps coverage where the finest level has a hole: coarser points
// the finest level does not reach join the flat level with their own radius.
TEST(MeshlessBasis, FlatteningCoversHolesOfTheFinestLevel) {
  std::vector<BasisPoint> points = plane_points(3, 1.0f, 0.25f);
  const glm::vec3 center(0.5f, 0.5f, 0.0f);
  std::erase_if(points, [&](const BasisPoint& p) {
    return p.level == 2 && glm::length(p.position - center) < 0.25f;
  });
  const BasisHierarchy basis(points);
  const std::vector<float> alpha = project_samples(basis, sample(basis, smooth_function), 1);
  const FlatExpansion flat = flatten(basis, alpha, 1);
  EXPECT_GT(flat.basis.size(), basis.level_end(2) - basis.level_begin(2));
  std::vector<glm::vec3> queries, normals;
  for (int i = 0; i < 20; ++i) {
    const float angle = 0.3f * float(i);
    queries.push_back(center + (0.01f * float(i)) * glm::vec3(std::cos(angle), std::sin(angle), 0));
    normals.push_back({0.0f, 0.0f, 1.0f});
  }
  std::vector<float> hierarchical(queries.size()), flat_values(queries.size());
  EXPECT_EQ(evaluate_many(basis, alpha, 1, queries, normals, hierarchical), 0u);
  EXPECT_EQ(evaluate_many(flat.basis, flat.coefficients, 1, queries, normals, flat_values), 0u);
  // Inside the hole the hierarchy has levels 0-1, the flat basis one Shepard level of the
  // few coarse points the finest level misses (plus the rim's finest points), which smooths
  // at the coarse scale. Measured max errors over jitter seeds 1-5: hierarchy 0.017-0.040,
  // flat 0.10-0.20 (the function's amplitude is 0.5). Coverage is the point here; the
  // bounds are 2x / 1.5x the worst seed.
  for (size_t q = 0; q < queries.size(); ++q) {
    EXPECT_NEAR(hierarchical[q], smooth_function(queries[q]), 0.08f);
    EXPECT_NEAR(flat_values[q], smooth_function(queries[q]), 0.3f);
  }
}

}  // namespace
}  // namespace bakegi::meshless
