// The path tracer's sampling contract: deterministic for a seed, independent of the thread
// count, progressive (samples [0, N) are the first N of any longer run, and runs with
// sample offsets average exactly to one long run), and converging to the closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <tbb/task_arena.h>

#include "light_transport_fixtures.h"
#include "util/error.h"
#include "util/random.h"

namespace bakegi {
namespace {

using test::BakeOptions;
using test::Baker;

constexpr float kAlbedo = 0.5f;
constexpr float kIntensity = 2.0f;

// A sphere of radius 1 (2 subdivisions: 320 triangles) with a point light at the centre.
SceneDescription small_sphere() {
  SceneDescription d;
  const uint32_t wall = test::add_material(d, glm::vec3(kAlbedo));
  d.meshes.push_back(test::make_icosphere(glm::vec3(0.0f), 1.0f, 2, wall));
  d.lights.push_back(test::point_light(glm::vec3(0.0f), glm::vec3(kIntensity)));
  return d;
}

// Points at the vertices of the sphere (exactly on the unit sphere), facing inwards.
BakePoints vertex_points(const SceneDescription& d, size_t count) {
  std::vector<glm::vec3> positions, normals;
  const auto& mesh = d.meshes[0];
  for (size_t i = 0; i < count && i < mesh.positions.size(); ++i) {
    positions.push_back(mesh.positions[i]);
    normals.push_back(-mesh.positions[i]);
  }
  return test::make_points(positions, normals);
}

bool bit_identical(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
}

TEST(PathTraceDeterminism, SameSeedIsBitIdenticalDifferentSeedsDiffer) {
  const SceneDescription d = small_sphere();
  Baker baker(d);
  const BakePoints points = vertex_points(d, 40);
  BakeOptions options;
  options.samples = 16;
  options.seed = 7;
  const auto first = baker.bake(points, options);
  const auto second = baker.bake(points, options);
  EXPECT_TRUE(bit_identical(first, second));
  options.seed = 8;
  const auto other = baker.bake(points, options);
  size_t differing = 0;
  for (size_t i = 0; i < points.size(); ++i) differing += other[i] != first[i];
  EXPECT_GT(differing, points.size() * 9 / 10);
}

TEST(PathTraceDeterminism, ThreadCountDoesNotChangeResults) {
  const SceneDescription d = small_sphere();
  Baker baker(d);
  const BakePoints points = vertex_points(d, 100);
  BakeOptions options;
  options.samples = 8;
  std::vector<glm::vec3> one, two;
  tbb::task_arena(1).execute([&] { one = baker.bake(points, options); });
  tbb::task_arena(2).execute([&] { two = baker.bake(points, options); });
  EXPECT_TRUE(bit_identical(one, two));
}

TEST(PathTraceDeterminism, SampleOffsetChunksAverageToOneRun) {
  const SceneDescription d = small_sphere();
  Baker baker(d);
  const BakePoints points = vertex_points(d, 40);
  BakeOptions options;
  options.samples = 24;
  const auto full = baker.bake(points, options);
  options.samples = 8;
  std::vector<glm::vec3> chunks[3];
  for (int k = 0; k < 3; ++k) {
    options.sample_offset = 8 * k;
    chunks[k] = baker.bake(points, options);
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::vec3 average = (chunks[0][i] + chunks[1][i] + chunks[2][i]) / 3.0f;
    for (int c = 0; c < 3; ++c) {
      // Each output is rounded to float once, the average once more: a few ulps.
      EXPECT_NEAR(average[c], full[i][c], 4e-7f * std::abs(full[i][c])) << "point " << i;
    }
  }
  // A chunk starting at 0 is the beginning of the long run, not a different estimator.
  EXPECT_FALSE(bit_identical(chunks[0], chunks[1]));
}

TEST(PathTraceDeterminism, MoreSamplesConvergeToTheClosedForm) {
  // rho I / (pi R^2 (1 - rho)); the sphere is coarse (320 triangles) so the expected value
  // uses the mesh's mean direct irradiance 4 pi I / A (see test_pathtrace_sphere.cpp) and
  // the RMSE is measured over points. Noise falls as 1/sqrt(N): 64x the samples must cut
  // the error well below half (expected ~1/8, down to the tessellation floor; measured
  // 0.16 -> 0.022).
  const SceneDescription d = small_sphere();
  double area = 0.0;
  const auto& m = d.meshes[0];
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const glm::dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]),
        c(m.positions[m.indices[t + 2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  const double expected = kAlbedo * kIntensity * 4.0 * M_PI / area / (M_PI * (1.0 - kAlbedo));
  Baker baker(d);
  const BakePoints points = vertex_points(d, 162);
  auto rmse = [&](int64_t samples) {
    BakeOptions options;
    options.samples = samples;
    const auto values = baker.bake(points, options);
    double sum = 0.0;
    for (const auto& v : values) sum += (v.x - expected) * (v.x - expected);
    return std::sqrt(sum / double(values.size())) / expected;
  };
  const double coarse = rmse(2);
  const double fine = rmse(128);
  EXPECT_LT(fine, 0.5 * coarse);
  EXPECT_LT(fine, 0.04);  // measured 0.022
  std::printf("relative RMSE: 2 samples %.4f, 128 samples %.4f\n", coarse, fine);
}

TEST(PathTraceDeterminism, EvaluateStopsWhenCancelled) {
  const SceneDescription d = small_sphere();
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  Settings settings;
  JobContext context;
  auto field =
      make_solver("pathtrace")->solve(SolveInputs{scene, tracer, direct, settings}, context);
  const BakePoints points = vertex_points(d, 100);
  std::vector<glm::vec3> out(points.size());
  context.cancel();
  try {
    field->evaluate(points, out, context);
    FAIL() << "evaluate ignored cancel";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_CANCELLED);
  }
}

TEST(PathTraceDeterminism, UnknownMethodAndBadSettingsAreRefused) {
  try {
    make_solver("photon");
    FAIL() << "unknown method accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(e.what()).find("known: pathtrace, direct"), std::string::npos);
  }
  const SceneDescription d = small_sphere();
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  JobContext context;
  for (const char* key : {"samples", "max_bounces"}) {
    Settings settings;
    settings.set(key, int64_t(0));
    EXPECT_THROW(
        make_solver("pathtrace")->solve(SolveInputs{scene, tracer, direct, settings}, context),
        Error)
        << key;
  }
}

}  // namespace
}  // namespace bakegi
