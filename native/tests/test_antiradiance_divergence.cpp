// A scene antiradiance cannot model: a dense cluster of small open leaves (single quads,
// each with a back side of its own) grouped into patches whose transport creates energy, so
// both iteration schemes grow from the first bounces on (as on the suite's living room and
// Sponza, docs/methods/antiradiance.md). Such a solve must not be handed out as a bake: with
// `fallback=1` (the default) it throws CannotModel, which the bake job answers with the path
// tracer (test_job.cpp, AMethodThatCannotModelTheSceneHandsTheBakeToThePathTracer, covers
// that hand-over for the memory budget); with `fallback=0` it keeps the last state that did
// not grow and says so.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "light_transport_fixtures.h"
#include "solvers/solver.h"
#include "util/error.h"
#include "util/random.h"

namespace bakegi::test {
namespace {

// A 4 x 4 x 2.5 m room lit by a lamp, with `leaves` 8 cm leaves at random tilts (up to 39°
// off vertical) in a 0.5 m cube around (0, 0, 0.6), twice (two leaf meshes of one plant, the
// second 3 cm higher, as the living room's plants are modelled).
SceneDescription room_with_leaf_cluster(int leaves) {
  SceneDescription d;
  const uint32_t walls = add_material(d, glm::vec3(0.6f));
  const uint32_t leaf = add_material(d, glm::vec3(0.5f, 0.6f, 0.3f));
  d.meshes.push_back(
      make_cube(glm::vec3(-2, -2, 0), glm::vec3(2, 2, 2.5f), Facing::kInward, walls));
  Pcg32 rng(7, 11);
  auto signed_unit = [&] { return 2.0f * rng.next_float() - 1.0f; };
  for (int copy = 0; copy < 2; ++copy) {
    Mesh mesh;
    for (int i = 0; i < leaves; ++i) {
      glm::vec3 c(0.25f * signed_unit(), 0.25f * signed_unit(), 0.6f + 0.25f * signed_unit());
      c.z += 0.03f * float(copy);
      const glm::vec3 n =
          glm::normalize(glm::vec3(0.8f * signed_unit(), 0.8f * signed_unit(), 1.0f));
      const glm::vec3 a = glm::normalize(glm::cross(n, glm::vec3(1, 0, 0)));
      const glm::vec3 b = glm::cross(n, a);
      const float h = 0.04f;
      const uint32_t base = uint32_t(mesh.positions.size());
      mesh.positions.insert(mesh.positions.end(),
                            {c - a * h - b * h, c + a * h - b * h, c + a * h + b * h,
                             c - a * h + b * h});
      mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    mesh.material = leaf;
    d.meshes.push_back(std::move(mesh));
  }
  d.lights.push_back(point_light(glm::vec3(0.5f, 0.3f, 2.2f), glm::vec3(30.0f)));
  return d;
}

BakePoints floor_grid(int side) {
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      positions.push_back(glm::vec3(-1.9f + 3.8f * float(i) / float(side - 1),
                                    -1.9f + 3.8f * float(j) / float(side - 1), 0.0f));
      normals.push_back(glm::vec3(0, 0, 1));
    }
  }
  return make_points(positions, normals);
}

TEST(AntiradianceDivergence, ALeafClusterThatMakesTheIterationGrowIsRefusedAsCannotModel) {
  const Scene scene = build_scene(room_with_leaf_cluster(200));
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  const BakePoints points = floor_grid(12);
  auto solve = [&](int64_t fallback, JobContext& context) {
    Settings settings;
    settings.set("fallback", fallback);
    auto solver = make_solver("antiradiance");
    return solver->solve(SolveInputs{scene, tracer, direct, settings, &points}, context);
  };

  JobContext refused;
  try {
    solve(1, refused);
    ADD_FAILURE() << "a diverging solve was handed out";
  } catch (const CannotModel& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_INVALID_SCENE);
    EXPECT_NE(std::string(e.what()).find("the iteration diverged"), std::string::npos) << e.what();
  }

  // fallback=0: the state of the last iteration that did not grow, with the reason.
  JobContext kept;
  const auto field = solve(0, kept);
  std::vector<glm::vec3> out(points.size());
  field->evaluate(points, out, kept);
  for (const glm::vec3& v : out) {
    EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
  }
  EXPECT_LE(kept.report().count("antiradiance_iterations"), 2u);
  bool said_so = false;
  for (const std::string& w : kept.report().warnings()) {
    said_so = said_so || w.find("kept the result of iteration") != std::string::npos;
  }
  EXPECT_TRUE(said_so);
}

}  // namespace
}  // namespace bakegi::test
