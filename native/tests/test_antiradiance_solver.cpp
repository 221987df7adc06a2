// The antiradiance solver end to end: settings, memory budget, iteration and interpolation
// at bake points, against a closed form and against the path tracer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "light_transport_fixtures.h"
#include "solvers/antiradiance/antiradiance_solver.h"
#include "util/error.h"
#include "error_metric.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

// Scene, tracer and direct light, then the antiradiance solver with the given settings.
class AntiradianceBaker {
 public:
  explicit AntiradianceBaker(const SceneDescription& description)
      : scene_(build_scene(description)), tracer_(scene_), direct_(scene_, tracer_) {}

  std::unique_ptr<IndirectField> solve(const Settings& settings, JobContext& context) {
    AntiradianceSolver solver;
    return solver.solve(SolveInputs{scene_, tracer_, direct_, settings}, context);
  }

  std::vector<glm::vec3> bake(const BakePoints& points, const Settings& settings,
                              JobContext& context) {
    const auto field = solve(settings, context);
    std::vector<glm::vec3> out(points.size());
    field->evaluate(points, out, context);
    return out;
  }

 private:
  Scene scene_;
  RayTracer tracer_;
  DirectLight direct_;
};

glm::vec3 uniform_direction(Pcg32& rng) {
  const float z = 1.0f - 2.0f * rng.next_float();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * rng.next_float();
  return {r * std::cos(phi), r * std::sin(phi), z};
}

bool all_finite(const std::vector<glm::vec3>& values) {
  for (const glm::vec3& v : values) {
    if (!(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z))) return false;
  }
  return true;
}

// A 2 m closed box (x, y in [-1, 1], z in [0, 2]) with inward faces: red wall at x = -1,
// green at x = +1, white elsewhere, a white solid cube (0.8 m, outward faces) on the floor
// and a point lamp below the ceiling. Coarse and Cornell-like.
SceneDescription cornell_box() {
  SceneDescription d;
  const uint32_t white = test::add_material(d, glm::vec3(0.7f));
  const uint32_t red = test::add_material(d, glm::vec3(0.7f, 0.1f, 0.1f));
  const uint32_t green = test::add_material(d, glm::vec3(0.1f, 0.7f, 0.1f));
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  test::add_quad(d, {0, 0, 0}, x, y, 1, 1, white);   // floor, +z
  test::add_quad(d, {0, 0, 2}, y, x, 1, 1, white);   // ceiling, -z
  test::add_quad(d, {-1, 0, 1}, y, z, 1, 1, red);    // +x
  test::add_quad(d, {1, 0, 1}, z, y, 1, 1, green);   // -x
  test::add_quad(d, {0, -1, 1}, z, x, 1, 1, white);  // +y
  test::add_quad(d, {0, 1, 1}, x, z, 1, 1, white);   // -y
  const glm::vec3 c(0.3f, 0.2f, 0.4f);
  const float h = 0.4f;
  test::add_quad(d, c + glm::vec3(0, 0, h), x, y, h, h, white);  // top, +z
  test::add_quad(d, c - glm::vec3(0, 0, h), y, x, h, h, white);  // bottom, -z
  test::add_quad(d, c + glm::vec3(h, 0, 0), y, z, h, h, white);  // +x
  test::add_quad(d, c - glm::vec3(h, 0, 0), z, y, h, h, white);  // -x
  test::add_quad(d, c + glm::vec3(0, h, 0), z, x, h, h, white);  // +y
  test::add_quad(d, c - glm::vec3(0, h, 0), x, z, h, h, white);  // -y
  d.lights.push_back(test::point_light({-0.2f, -0.1f, 1.6f}, glm::vec3(8.0f)));
  return d;
}

// Bake points on the room's walls (inward normals), kept 0.05 m from the edges and off the
// cube's footprint.
BakePoints cornell_points(int per_wall) {
  std::vector<glm::vec3> positions, normals;
  Pcg32 rng(2024, 7);
  const glm::vec3 inward[6] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  for (const glm::vec3& n : inward) {
    for (int i = 0; i < per_wall;) {
      const float a = -0.95f + 1.9f * rng.next_float(), b = -0.95f + 1.9f * rng.next_float();
      glm::vec3 p;
      if (n.z != 0.0f) p = {a, b, n.z > 0 ? 0.0f : 2.0f};
      if (n.x != 0.0f) p = {n.x > 0 ? -1.0f : 1.0f, a, 1.0f + b};
      if (n.y != 0.0f) p = {a, n.y > 0 ? -1.0f : 1.0f, 1.0f + b};
      if (n.z > 0 && std::abs(p.x - 0.3f) < 0.45f && std::abs(p.y - 0.2f) < 0.45f) continue;
      positions.push_back(p);
      normals.push_back(n);
      ++i;
    }
  }
  return test::make_points(positions, normals);
}

TEST(AntiradianceSolver, ClosedSphereWithCentralLampMatchesClosedForm) {
  // See test_pathtrace_sphere.cpp: the bake value is ρ E0 / (π (1 − ρ)) everywhere, with E0
  // the mean direct irradiance 4π I / A_mesh. Every link here is unoccluded (a convex
  // enclosure seen from inside), so what remains is the directional discretization (Eq. 17's
  // point-to-point form factors over bins of 4π/m) and the hierarchy's cluster links, which
  // move energy with one center-to-center direction; the geometric series amplifies their
  // per-bounce error by 1/(1 − ρ) = 2. Measured mean error (deterministic: the lamp at the
  // center makes every direct sample exact): −20.8% at 48 bins, −2.1% at 192, +1.1% at 300
  // (the default, tested here), +1.3% at 768, so the error is the bins' and shrinks with
  // them. 3% bounds the default; a lost bounce would be 50% off, antiradiance leaking through
  // the wall or a missing spreading weight far more than 1%.
  const float rho = 0.5f;
  const glm::vec3 intensity(4.0f, 2.0f, 1.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, glm::vec3(rho));
  // Antiradiance treats surfaces as the boundaries of solids (§3.1): the room is the
  // inside of the sphere, so its faces must face inward (the fixture winds them outward).
  Mesh sphere = test::make_icosphere(glm::vec3(0.0f), 1.5f, 3, wall);
  for (size_t t = 0; t < sphere.indices.size(); t += 3) {
    std::swap(sphere.indices[t + 1], sphere.indices[t + 2]);
  }
  d.meshes.push_back(std::move(sphere));
  d.lights.push_back(test::point_light(glm::vec3(0.0f), intensity));
  const double area = test::mesh_area(d.meshes[0]);
  const glm::dvec3 expected =
      glm::dvec3(intensity) * (4.0 * M_PI / area) * double(rho) / (M_PI * (1.0 - rho));

  std::vector<glm::vec3> positions, normals;
  Pcg32 rng(5, 9);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 n = uniform_direction(rng);
    positions.push_back(n * 1.499f);
    normals.push_back(-n);
  }
  AntiradianceBaker baker(d);
  Settings settings;
  JobContext context;
  const auto values = baker.bake(test::make_points(positions, normals), settings, context);
  ASSERT_TRUE(all_finite(values));
  glm::dvec3 mean(0.0), worst(0.0);
  for (const glm::vec3& v : values) {
    mean += glm::dvec3(v) / double(values.size());
    worst = glm::max(worst, glm::abs(glm::dvec3(v) / expected - 1.0));
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(mean[c], expected[c], 0.03 * expected[c]) << "channel " << c;
    EXPECT_LT(worst[c], 0.06) << "channel " << c;  // uniform up to the bins' aliasing
  }
  std::printf("sphere: expected %.5f, mean %.5f (%+.2f%%), worst point %.2f%%, %llu links\n",
              expected.x, mean.x, 100.0 * (mean.x / expected.x - 1.0), 100.0 * worst.x,
              (unsigned long long)context.report().count("antiradiance_links"));
}

TEST(AntiradianceSolver, CornellBoxAgreesWithPathTracer) {
  // 72 points on the room's walls; reference: the path tracer, 4096 paths per point.
  const SceneDescription d = cornell_box();
  const BakePoints points = cornell_points(12);
  test::Baker reference_baker(d);
  test::BakeOptions reference;
  reference.samples = 4096;
  const auto expected = reference_baker.bake(points, reference);

  AntiradianceBaker baker(d);
  Settings settings;  // defaults: 300 bins, patches of extent / 16
  JobContext context;
  const auto values = baker.bake(points, settings, context);
  ASSERT_TRUE(all_finite(values));
  const auto error = relative_rmse_luminance(&values[0].x, &expected[0].x, values.size());
  ASSERT_TRUE(error.has_value());
  const Report& report = context.report();
  std::printf(
      "cornell: relative RMSE %.2f%% vs path tracer; %llu elements, %llu links, %llu "
      "iterations\n",
      100.0 * *error, (unsigned long long)report.count("antiradiance_elements"),
      (unsigned long long)report.count("antiradiance_links"),
      (unsigned long long)report.count("antiradiance_iterations"));
  // Measured 2.9% at the defaults (printed; 4.2% at 192 bins with twice finer patches and no
  // near-field gather). Part of it is the reference's own noise: two path-traced references
  // with different seeds differ by 2.2%, so each holds about 1.5%; the rest is the method's
  // bias (mostly the bins, as on the sphere). 7% leaves room for that noise and for legitimate
  // changes of the passes, while a lost bounce (the second one alone adds 29% of the total here),
  // light leaking through the cube or a broken interpolation give far more.
  EXPECT_LT(*error, 0.07);
  EXPECT_GT(report.count("antiradiance_links"), 0u);
  EXPECT_GT(report.count("antiradiance_iterations"), 0u);
}

TEST(AntiradianceSolver, SmallMemoryBudgetCoarsensOrRefusesWithMessage) {
  AntiradianceBaker baker(cornell_box());
  const BakePoints points = cornell_points(2);
  {
    // Automatic patch size: the default (extent / 16) needs far more than 8 MB at 300 bins,
    // so it is coarsened, with a warning, and still gives finite values.
    Settings settings;
    settings.set("memory_budget_mb", int64_t(8));
    JobContext context;
    const auto values = baker.bake(points, settings, context);
    EXPECT_TRUE(all_finite(values));
    const auto warnings = context.report().warnings();
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings.front().find("coarsened"), std::string::npos) << warnings.front();
    EXPECT_LT(context.report().count("antiradiance_table_bytes") +
                  context.report().count("antiradiance_link_bytes"),
              uint64_t(8) << 20);
  }
  {
    // A requested patch size is not changed: refused, naming one that fits.
    Settings settings;
    settings.set("memory_budget_mb", int64_t(8));
    settings.set("patch_size", 0.02);
    JobContext context;
    try {
      baker.solve(settings, context);
      FAIL() << "expected a refusal";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY);
      EXPECT_NE(std::string(e.what()).find("patch_size"), std::string::npos) << e.what();
    }
  }
  {
    // 1 MB cannot hold even the unsplit triangles' tables at 3072 bins.
    Settings settings;
    settings.set("memory_budget_mb", int64_t(1));
    settings.set("bins", int64_t(3072));
    JobContext context;
    try {
      baker.solve(settings, context);
      FAIL() << "expected a refusal";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY);
      EXPECT_NE(std::string(e.what()).find("memory_budget_mb"), std::string::npos) << e.what();
    }
  }
}

TEST(AntiradianceSolver, EveryBakePointIsFiniteEvenFarFromPatches) {
  AntiradianceBaker baker(cornell_box());
  Settings settings;
  settings.set("patch_size", 0.25);
  JobContext context;
  const auto field = baker.solve(settings, context);
  std::vector<glm::vec3> positions = {{100, 100, 100}, {0, 0, 1}, {1e6f, -1e6f, 0}, {0, 0, 0}};
  std::vector<glm::vec3> normals = {{0, 0, 1}, {1, 1, 1}, {0, -1, 0}, {0, 0, -1}};
  Pcg32 rng(3, 4);
  for (int i = 0; i < 500; ++i) {
    positions.push_back(glm::vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 6.0f -
                        3.0f);
    normals.push_back(uniform_direction(rng));
  }
  const BakePoints points = test::make_points(positions, normals);
  std::vector<glm::vec3> out(points.size(), glm::vec3(NAN));
  field->evaluate(points, out, context);
  EXPECT_TRUE(all_finite(out));
  for (const glm::vec3& v : out) EXPECT_GE(glm::min(v.x, glm::min(v.y, v.z)), 0.0f);
  // A point far away facing up sees nothing above it: off every surface it gathers from the
  // solution and gets no light (it used to take the nearest upward patch's, issue 18).
  EXPECT_EQ(out[0], glm::vec3(0.0f));
}

TEST(AntiradianceSolver, CancelStopsSolveAndEvaluate) {
  AntiradianceBaker baker(cornell_box());
  Settings settings;
  settings.set("patch_size", 0.25);
  {
    JobContext context;
    context.cancel();
    try {
      baker.solve(settings, context);
      FAIL() << "expected cancellation";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_CANCELLED);
    }
  }
  JobContext context;
  const auto field = baker.solve(settings, context);
  const BakePoints points = cornell_points(4);
  std::vector<glm::vec3> out(points.size());
  context.cancel();
  try {
    field->evaluate(points, out, context);
    FAIL() << "expected cancellation";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_CANCELLED);
  }
}

TEST(AntiradianceSolver, BadSettingsAreRefused) {
  AntiradianceBaker baker(cornell_box());
  for (const auto& [key, value] : std::vector<std::pair<std::string, SettingValue>>{
           {"bins", int64_t(4)}, {"scheme", std::string("sideways")}, {"patch_size", -1.0}}) {
    Settings settings;
    settings.set(key, value);
    JobContext context;
    try {
      baker.solve(settings, context);
      FAIL() << "expected a refusal of " << key;
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_INVALID_ARGUMENT) << key;
    }
  }
}

// ---- Open meshes and zero-thickness walls (back_sides.h, mesh_topology.h) ----

// Two 1 m rooms side by side, A at x in [-1, 0], B at x in [0, 1], each an inward box shell
// open at x = 0, divided there by one plane facing A (`plane_faces_a`) or B. A point lamp
// lights A only: B's exact indirect light is 0.
SceneDescription rooms_divided_by_a_plane(bool plane_faces_a) {
  SceneDescription d;
  const uint32_t white = test::add_material(d, glm::vec3(0.7f));
  // make_cube's faces are 6 indices each in the order z lo, z hi, y lo, y hi, x lo, x hi.
  Mesh a = test::make_cube({-1, -0.5f, 0}, {0, 0.5f, 1}, test::Facing::kInward, white);
  a.indices.erase(a.indices.begin() + 30, a.indices.begin() + 36);  // x hi
  Mesh b = test::make_cube({0, -0.5f, 0}, {1, 0.5f, 1}, test::Facing::kInward, white);
  b.indices.erase(b.indices.begin() + 24, b.indices.begin() + 30);  // x lo
  d.meshes.push_back(std::move(a));
  d.meshes.push_back(std::move(b));
  const glm::vec3 y(0, 1, 0), z(0, 0, 1);
  // add_quad's normal is u x v: z x y = -x (towards A), y x z = +x (towards B).
  if (plane_faces_a) {
    test::add_quad(d, {0, 0, 0.5f}, z, y, 0.5f, 0.5f, white);
  } else {
    test::add_quad(d, {0, 0, 0.5f}, y, z, 0.5f, 0.5f, white);
  }
  d.lights.push_back(test::point_light({-0.5f, 0, 0.8f}, glm::vec3(2.0f)));
  return d;
}

// A grid of bake points on each room's floor and on its wall opposite the plane.
BakePoints divided_rooms_points(float room_sign) {
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const float u = (float(i) + 0.5f) / 8.0f, v = (float(j) + 0.5f) / 8.0f;
      positions.push_back({room_sign * (0.05f + 0.9f * u), -0.45f + 0.9f * v, 0.0f});
      normals.push_back({0, 0, 1});
      positions.push_back({room_sign * 1.0f, -0.45f + 0.9f * v, 0.05f + 0.9f * u});
      normals.push_back({-room_sign, 0, 0});
    }
  }
  return test::make_points(positions, normals);
}

double mean_luminance(const std::vector<glm::vec3>& values) {
  double sum = 0.0;
  for (const glm::vec3& v : values) {
    sum += kLuminanceWeights[0] * v.x + kLuminanceWeights[1] * v.y + kLuminanceWeights[2] * v.z;
  }
  return sum / double(values.size());
}

TEST(AntiradianceOpenMeshes, ZeroThicknessWallKeepsTheDarkRoomDarkWhicheverWayItFaces) {
  double a_level[2] = {0.0, 0.0};
  for (const bool plane_faces_a : {true, false}) {
    SCOPED_TRACE(plane_faces_a ? "plane faces the lit room" : "plane faces the dark room");
    const SceneDescription d = rooms_divided_by_a_plane(plane_faces_a);
    AntiradianceBaker baker(d);
    Settings settings;
    settings.set("bins", int64_t(108));
    settings.set("patch_size", 0.1);
    JobContext context;
    const auto field = baker.solve(settings, context);
    const BakePoints a_points = divided_rooms_points(-1.0f), b_points = divided_rooms_points(1.0f);
    std::vector<glm::vec3> a(a_points.size()), b(b_points.size());
    field->evaluate(a_points, a, context);
    field->evaluate(b_points, b, context);
    ASSERT_TRUE(all_finite(a) && all_finite(b));
    a_level[plane_faces_a ? 0 : 1] = mean_luminance(a);
    const double leakage = mean_luminance(b) / mean_luminance(a);
    std::printf("divided rooms, plane facing %s: A %.5f, leakage B/A %.2f%%, %llu patches\n",
                plane_faces_a ? "A" : "B", mean_luminance(a), 100.0 * leakage,
                (unsigned long long)context.report().count("antiradiance_patches"));
    // All three meshes are open, and the user is told so.
    const auto warnings = context.report().warnings();
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings.back().find("3 meshes do not bound a solid"), std::string::npos)
        << warnings.back();
    // Measured 1.65% (plane facing A) and 1.31% (facing B): what antiradiance cancels only to
    // the bins' resolution (point-collocated, 108 bins here; the thick-walled two-rooms scene
    // of closed solids leaks 2.6% at 192). Without back sides the plane facing B lets A's
    // light through unblocked: 64%.
    EXPECT_LT(leakage, 0.03);
  }
  // With the plane's other side a surface of its own, which way its normal points does not
  // change room A: that side reflects A's light either way. Measured 0.2% apart; without back
  // sides A loses the wall's reflection when it faces B (40% darker).
  EXPECT_NEAR(a_level[1], a_level[0], 0.03 * a_level[0]);
}

// The splat is smooth across patch borders: along a line across the ceiling at 2.5 mm steps
// no step changes the value by more than 0.5% of its mean. (A quilt of per-patch values, as
// an early Material Preview showed, jumps by a few percent at every patch border; a smooth
// field changes by about 0.1% per step here, its slope times 2.5 mm.)
TEST(AntiradianceSolver, TheSplatIsSmoothAcrossPatchBorders) {
  AntiradianceBaker baker(cornell_box());
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i <= 720; ++i) {
    positions.push_back({-0.9f + 0.0025f * float(i), 0.05f, 2.0f});
    normals.push_back({0, 0, -1});
  }
  const BakePoints points = test::make_points(positions, normals);
  JobContext context;
  const std::vector<glm::vec3> values = baker.bake(points, Settings{}, context);
  auto luminance = [](const glm::vec3& c) {
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
  };
  double mean = 0.0;
  for (const glm::vec3& v : values) mean += luminance(v) / double(values.size());
  ASSERT_GT(mean, 0.0);
  double largest_step = 0.0;
  for (size_t i = 1; i < values.size(); ++i) {
    largest_step = std::max(largest_step, std::abs(luminance(values[i]) - luminance(values[i - 1])));
  }
  std::printf("largest step along the ceiling: %.3f%% of the mean\n", 100.0 * largest_step / mean);
  EXPECT_LT(largest_step / mean, 0.005);
}

}  // namespace
}  // namespace bakegi
