// The Embree wrapper: exact hits on known triangles (distance and barycentrics), both
// sides of a triangle, occlusion, misses, watertightness of a closed box, packets agreeing
// with single rays, the hit's own point and normal, the per-triangle shading records, and the
// memory budget and cancel hooks of the build.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

SceneDescription lit_description() {
  SceneDescription d;
  d.materials.push_back(Material{});
  Light light;
  light.color = glm::vec3(1.0f);
  d.lights.push_back(light);
  return d;
}

// One triangle (0,0,0), (1,0,0), (0,1,0) in the plane z = 0, after a degenerate one that
// build_scene drops, so the hit must name the surviving triangle's index.
Scene one_triangle_scene() {
  SceneDescription d = lit_description();
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  mesh.indices = {0, 1, 3, 0, 1, 2};
  d.meshes.push_back(mesh);
  return build_scene(d);
}

// The cube [-1,1]^3 as 12 triangles.
Scene cube_scene() {
  SceneDescription d = lit_description();
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
  }
  mesh.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                  2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  d.meshes.push_back(mesh);
  return build_scene(d);
}

TEST(RayTracer, HitDistanceAndBarycentrics) {
  const Scene scene = one_triangle_scene();
  ASSERT_EQ(scene.triangles.size(), 1u);
  const RayTracer tracer(scene);
  const Hit hit = tracer.intersect({{0.25f, 0.125f, 1.0f}, {0, 0, -1}});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.triangle, 0u);
  EXPECT_EQ(scene.triangles[hit.triangle].mesh_triangle, 1u);
  // Exact in float: the plane is z = 0 and the point lies on the dyadic grid.
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_NEAR(hit.b1, 0.25f, 1e-6f);   // weight of corner 1 = (1,0,0): the x coordinate
  EXPECT_NEAR(hit.b2, 0.125f, 1e-6f);  // weight of corner 2 = (0,1,0): the y coordinate

  // t is in units of |direction|.
  const Hit scaled = tracer.intersect({{0.25f, 0.125f, 1.0f}, {0, 0, -4}});
  ASSERT_TRUE(scaled.hit);
  EXPECT_FLOAT_EQ(scaled.t, 0.25f);
}

TEST(RayTracer, BothSidesAreHit) {
  const Scene scene = one_triangle_scene();
  const RayTracer tracer(scene);
  const Hit from_below = tracer.intersect({{0.1f, 0.1f, -2.0f}, {0, 0, 1}});
  ASSERT_TRUE(from_below.hit);
  EXPECT_FLOAT_EQ(from_below.t, 2.0f);
}

TEST(RayTracer, MissesAndRayIntervals) {
  const Scene scene = one_triangle_scene();
  const RayTracer tracer(scene);
  EXPECT_FALSE(tracer.intersect({{0.6f, 0.6f, 1.0f}, {0, 0, -1}}).hit);  // beyond the diagonal
  EXPECT_FALSE(tracer.intersect({{0.2f, 0.2f, 1.0f}, {0, 0, 1}}).hit);   // pointing away
  Ray short_ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}};
  short_ray.tfar = 0.99f;
  EXPECT_FALSE(tracer.intersect(short_ray).hit);
  EXPECT_FALSE(tracer.occluded(short_ray));
  short_ray.tfar = 1.01f;
  EXPECT_TRUE(tracer.occluded(short_ray));
  Ray late_start{{0.2f, 0.2f, 1.0f}, {0, 0, -1}};
  late_start.tnear = 1.01f;
  EXPECT_FALSE(tracer.intersect(late_start).hit);
  EXPECT_FALSE(tracer.occluded(late_start));
}

TEST(RayTracer, ClosedCubeIsWatertight) {
  const Scene scene = cube_scene();
  const RayTracer tracer(scene);
  std::mt19937 rng(7);
  std::normal_distribution<float> gauss;
  std::uniform_real_distribution<float> uniform(-0.9f, 0.9f);
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 origin(uniform(rng), uniform(rng), uniform(rng));
    const glm::vec3 direction = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
    const Hit hit = tracer.intersect({origin, direction});
    ASSERT_TRUE(hit.hit) << "ray " << i << " escaped the closed cube";
    // Distance to the first face the ray reaches: min over axes of (±1 - o) / d.
    float expected = 1e30f;
    for (int k = 0; k < 3; ++k) {
      if (direction[k] != 0) {
        expected =
            std::min(expected, ((direction[k] > 0 ? 1.0f : -1.0f) - origin[k]) / direction[k]);
      }
    }
    // Float intersection error is a few ulps of the distances involved (< 4).
    ASSERT_NEAR(hit.t, expected, 1e-5f) << "ray " << i;
    const Triangle& t = scene.triangles[hit.triangle];
    const glm::vec3 p = (1 - hit.b1 - hit.b2) * t.p[0] + hit.b1 * t.p[1] + hit.b2 * t.p[2];
    ASSERT_NEAR(glm::length(p - (origin + hit.t * direction)), 0.0f, 1e-5f);
    // The hit carries its point and Embree's normal, so shading need not load the Triangle.
    ASSERT_NEAR(glm::length(hit.position - p), 0.0f, 1e-5f) << "ray " << i;
    const glm::vec3 normal = glm::normalize(hit.normal);
    ASSERT_NEAR(std::abs(glm::dot(normal, t.face_normal)), 1.0f, 1e-6f) << "ray " << i;
  }
}

// Shading reads TriangleShading: the material, and whether the corners' normals differ from
// the face's (only then does a hit load the Triangle's normals).
TEST(RayTracer, ShadingRecordsMatchTriangles) {
  SceneDescription d = lit_description();
  d.materials.push_back(Material{});
  Mesh flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  flat.indices = {0, 1, 2};
  flat.material = 1;
  Mesh smooth = flat;
  smooth.material = 0;
  smooth.corner_normals = {{0, 0, 1}, {0, 0.6f, 0.8f}, {0, 0, 1}};
  Mesh given_flat = flat;  // normals given, all equal to the face's
  given_flat.corner_normals = {{0, 0, 2}, {0, 0, 1}, {0, 0, 1}};
  d.meshes.push_back(flat);
  d.meshes.push_back(smooth);
  d.meshes.push_back(given_flat);
  const Scene scene = build_scene(d);
  ASSERT_EQ(scene.shading.size(), scene.triangles.size());
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    EXPECT_EQ(scene.shading[i].material, scene.triangles[i].material);
  }
  EXPECT_EQ(scene.shading[0].smooth, 0u);
  EXPECT_EQ(scene.shading[1].smooth, 1u);
  EXPECT_EQ(scene.shading[2].smooth, 0u);
  for (const TriangleShading& s : scene.shading) EXPECT_EQ(s.sliver, 0u);
}

// A sliver on a tilted plane (twice its area 5e-7 of its longest edge squared, kept by
// validation): float's cross product of its edges loses most of its digits, so the hit's
// surface reads the face normal computed in double.
TEST(RayTracer, ASliverKeepsItsExactNormal) {
  SceneDescription d = lit_description();
  const glm::vec3 n = glm::normalize(glm::vec3(1, 2, 3));
  const glm::vec3 u = glm::normalize(glm::vec3(2, -1, 0));
  const glm::vec3 v = glm::cross(n, u);
  const glm::vec3 base(1.0f, 2.0f, 3.0f);
  Mesh sliver;
  sliver.positions = {base, base + u, base + 0.5f * u + 5e-7f * v};
  sliver.indices = {0, 1, 2};
  d.meshes.push_back(sliver);
  const Scene scene = build_scene(d);
  ASSERT_EQ(scene.triangles.size(), 1u);
  EXPECT_EQ(scene.shading[0].sliver, 1u);
  const RayTracer tracer(scene);
  const glm::vec3 direction = -n;
  const Hit hit = tracer.intersect({base + 0.5f * u + 2.5e-7f * v + n, direction});
  ASSERT_TRUE(hit.hit);
  const SurfacePoint x = surface_at_hit(scene, hit, direction);
  const glm::vec3 exact = scene.triangles[0].face_normal;
  EXPECT_NEAR(std::abs(glm::dot(x.geometric_normal, exact)), 1.0f, 1e-7f);
  // Facing the ray's side (the rounded vertices tilt the stored plane by a few degrees).
  EXPECT_GT(glm::dot(x.geometric_normal, n), 0.9f);
  EXPECT_NEAR(glm::dot(x.shading_normal, x.geometric_normal), 1.0f, 1e-7f);
}

TEST(RayTracer, PacketsAgreeWithSingleRays) {
  const Scene scene = cube_scene();
  const RayTracer tracer(scene);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uniform(-1.5f, 1.5f);
  std::vector<Ray> rays(1000);  // not a multiple of 16: the last packet is partial
  for (Ray& ray : rays) {
    ray.origin = {uniform(rng), uniform(rng), uniform(rng)};
    ray.direction = {uniform(rng), uniform(rng), uniform(rng)};
  }
  std::vector<Hit> hits(rays.size());
  tracer.intersect_many(rays.data(), hits.data(), rays.size());
  int hit_count = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Hit single = tracer.intersect(rays[i]);
    ASSERT_EQ(single.hit, hits[i].hit) << i;
    if (!single.hit) continue;
    ++hit_count;
    EXPECT_EQ(single.triangle, hits[i].triangle);
    EXPECT_NEAR(single.t, hits[i].t, 1e-5f * single.t);
    EXPECT_NEAR(glm::length(single.position - hits[i].position), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(glm::normalize(single.normal), glm::normalize(hits[i].normal)), 1.0f,
                1e-6f);
  }
  EXPECT_GT(hit_count, 300);  // origins inside the cube always hit: about 30% of them
  EXPECT_GT(tracer.memory_bytes(), 0u);
}

// The stream interface (benchmarks) returns what single rays return, ray by ray, at any chunk
// size, the last chunk partial; shadow rays with limited intervals.
TEST(RayTracer, StreamsAgreeWithSingleRays) {
  const Scene scene = cube_scene();
  const RayTracer tracer(scene);
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> uniform(-1.5f, 1.5f);
  std::uniform_real_distribution<float> length(0.0f, 3.0f);
  std::vector<Ray> rays(1000);
  for (Ray& ray : rays) {
    ray.origin = {uniform(rng), uniform(rng), uniform(rng)};
    ray.direction = glm::normalize(glm::vec3(uniform(rng), uniform(rng), uniform(rng)));
  }
  std::vector<Ray> segments = rays;
  for (Ray& segment : segments) segment.tfar = length(rng);
  for (const size_t chunk : {size_t(1), size_t(16), size_t(300), RayTracer::kMaxStreamChunk}) {
    std::vector<Hit> hits(rays.size());
    std::vector<uint8_t> blocked(segments.size(), 2);
    tracer.intersect_stream(rays.data(), hits.data(), rays.size(), chunk);
    tracer.occluded_stream(segments.data(), blocked.data(), segments.size(), chunk);
    int hit_count = 0, blocked_count = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const Hit single = tracer.intersect(rays[i]);
      ASSERT_EQ(single.hit, hits[i].hit) << chunk << " " << i;
      ASSERT_EQ(tracer.occluded(segments[i]) ? 1 : 0, blocked[i]) << chunk << " " << i;
      blocked_count += blocked[i];
      if (!single.hit) continue;
      ++hit_count;
      EXPECT_EQ(single.triangle, hits[i].triangle);
      EXPECT_NEAR(single.t, hits[i].t, 1e-5f * single.t);
      EXPECT_NEAR(glm::length(single.position - hits[i].position), 0.0f, 1e-5f);
    }
    EXPECT_GT(hit_count, 300);
    EXPECT_GT(blocked_count, 100);
    EXPECT_LT(blocked_count, 900);  // both answers occur
  }
}

// A grid of n x n quads in the plane z = 0: enough triangles for Embree to report build
// progress and allocate real memory.
Scene grid_scene(int n) {
  SceneDescription d = lit_description();
  Mesh mesh;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) mesh.positions.push_back({float(i) / n, float(j) / n, 0.0f});
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n) + 1, e = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, e, a, e, c});
    }
  }
  d.meshes.push_back(mesh);
  return build_scene(d);
}

TEST(RayTracer, MemoryBudgetAndCancelStopTheBuild) {
  const Scene scene = grid_scene(200);  // 80,000 triangles
  try {
    RayTracerOptions options;
    options.memory_budget_bytes = 1 << 20;  // far below what 80k triangles need
    const RayTracer tracer(scene, options);
    ADD_FAILURE() << "the build ignored its memory budget";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_OUT_OF_MEMORY) << e.what();
  }
  try {
    RayTracerOptions options;
    options.progress = [](double) { return false; };
    const RayTracer tracer(scene, options);
    ADD_FAILURE() << "the build ignored cancel";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_CANCELLED) << e.what();
  }
  const RayTracer tracer(scene);
  // The per-triangle figure the job's memory estimate relies on (bake_job.cpp).
  const double per_triangle = double(tracer.memory_bytes()) / scene.triangles.size();
  EXPECT_LT(per_triangle, 48.0 + 160.0);
  RecordProperty("embree_bytes_per_triangle", std::to_string(per_triangle));
}

}  // namespace
}  // namespace bakegi::test
