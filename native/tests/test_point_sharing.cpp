// Bake points that share one value (bake/point_sharing.h): corners of one vertex are baked
// once where they see the same light, and kept apart where a wall stands on the vertex. The
// scene is a floor with a single-sided wall standing on the line x = 0 and a point lamp on
// the +x side: the floor on the -x side gets no light at all, direct or indirect (it sees
// only the wall's unlit side and the black world), so a corner there must bake exactly 0,
// while the corners of the same vertex on the lit side bake more than 0.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bake/bake_job.h"
#include "bake/point_sharing.h"
#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "settings/settings.h"
#include "util/error.h"

namespace bakegi {
namespace {

using test::add_material;
using test::add_quad;

SceneDescription floor_with_wall() {
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.8f));
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  add_quad(d, {0, 0, 0}, x, y, 2, 1, white);  // the floor, normal +z
  add_quad(d, {0, 0, 1}, y, z, 1, 1, white);  // the wall on x = 0, normal +x
  d.lights.push_back(test::point_light({1, 0, 1}, glm::vec3(10.0f)));
  return d;
}

constexpr float kNudge = 0.002f;  // how far the exporter moves a corner into its face

// The corners of two vertices: (0, 0) under the wall and (0.5, 0.5) in the open, each with
// four corners moved into the four faces around it; every corner names its vertex's first.
BakePoints corners() {
  BakePoints points;
  const glm::vec2 vertices[] = {{0.0f, 0.0f}, {0.5f, 0.5f}};
  const glm::vec2 into_face[] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (const glm::vec2& v : vertices) {
    const uint32_t first = uint32_t(points.size());
    for (const glm::vec2& f : into_face) {
      points.positions.push_back(glm::vec3(v + kNudge * f, 0.0f));
      points.normals.push_back(glm::vec3(0, 0, 1));
      points.object_ids.push_back(0);
      points.share_candidates.push_back(first);
    }
  }
  return points;
}

std::vector<glm::vec3> bake(BakePoints points, std::string* report = nullptr) {
  Settings settings;
  settings.set("method", std::string("pathtrace"));
  settings.set("samples", int64_t(256));
  settings.set("error_probes", int64_t(0));
  BakeJob job(floor_with_wall(), std::move(points), settings);
  std::string message;
  EXPECT_EQ(job.wait(message), BAKEGI_OK) << message;
  if (report) *report = job.report_json();
  return job.results();
}

TEST(PointSharing, CornersOnTheTwoSidesOfAWallKeepTheirOwnLight) {
  const BakePoints points = corners();
  std::string report;
  const std::vector<glm::vec3> values = bake(points, &report);
  ASSERT_EQ(values.size(), 8u);
  // Lit side of the wall (corners 0 and 3) > 0; dark side (1 and 2) exactly 0.
  EXPECT_GT(values[0].y, 0.0f);
  EXPECT_EQ(values[3], values[0]);
  EXPECT_EQ(values[1], glm::vec3(0.0f));
  EXPECT_EQ(values[2], glm::vec3(0.0f));
  // In the open all four corners share one value.
  for (int i = 5; i < 8; ++i) EXPECT_EQ(values[i], values[4]);
  // Three evaluations: the lit side, the dark side, the open vertex.
  EXPECT_NE(report.find("\"evaluated_points\": 3"), std::string::npos) << report;
}

TEST(PointSharing, GroupsAreFoundWithOneRayPerPoint) {
  const Scene scene = build_scene(floor_with_wall());
  const RayTracer tracer(scene);
  const SharedPoints shared = share_points(corners(), tracer, 1e-4f);
  ASSERT_EQ(shared.distinct.size(), 3u);
  EXPECT_EQ(shared.distinct_index, (std::vector<uint32_t>{0, 1, 1, 0, 2, 2, 2, 2}));
  // The dark side is evaluated at its first corner, not at the lit one.
  EXPECT_LT(shared.distinct.positions[1].x, 0.0f);
}

TEST(PointSharing, NormalsThatDifferAreNotShared) {
  BakePoints points = corners();
  points.normals[5] = glm::normalize(glm::vec3(0.1f, 0.0f, 1.0f));  // 5.7 degrees off
  const Scene scene = build_scene(floor_with_wall());
  const RayTracer tracer(scene);
  const SharedPoints shared = share_points(points, tracer, 1e-4f);
  EXPECT_EQ(shared.distinct.size(), 4u);
  EXPECT_NE(shared.distinct_index[5], shared.distinct_index[4]);
}

TEST(PointSharing, WithoutCandidatesEveryPointIsItsOwn) {
  BakePoints points = corners();
  points.share_candidates.clear();
  const Scene scene = build_scene(floor_with_wall());
  const RayTracer tracer(scene);
  EXPECT_TRUE(share_points(points, tracer, 1e-4f).distinct_index.empty());
  std::string report;
  bake(points, &report);
  EXPECT_NE(report.find("\"evaluated_points\": 8"), std::string::npos) << report;
}

TEST(PointSharing, CandidatesMustNameAnEarlierGroupStart) {
  EXPECT_NO_THROW(check_share_candidates(std::vector<uint32_t>{0, 0, 2, 2}, 4));
  EXPECT_NO_THROW(check_share_candidates(std::vector<uint32_t>{}, 4));
  EXPECT_THROW(check_share_candidates(std::vector<uint32_t>{0, 2, 2}, 3), Error);  // later
  EXPECT_THROW(check_share_candidates(std::vector<uint32_t>{0, 0, 1}, 3), Error);  // chain
  EXPECT_THROW(check_share_candidates(std::vector<uint32_t>{0, 0}, 3), Error);     // count
}

}  // namespace
}  // namespace bakegi
