// The visibility test of the antiradiance output splat (surface_interpolation.h): a bake point
// does not average patches it cannot see along the surface (a box standing on a floor hides
// the floor under it), yet on a curved surface every neighbour stays visible.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "light_transport_fixtures.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "solvers/antiradiance/surface_interpolation.h"

namespace bakegi::test {
namespace {

using antiradiance::SurfaceInterpolation;
using antiradiance::SurfaceSample;

constexpr float kBoxHalf = 0.2f;  // the box covers |x|, |y| < 0.2 of the floor

// A 2 m floor and a 0.4 m box standing on it, and floor samples every 0.05 m: value 1 where
// the floor is open, 0 under the box (where no light arrives).
struct FloorWithBox {
  FloorWithBox() {
    SceneDescription d;
    const uint32_t white = add_material(d, glm::vec3(0.5f));
    add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1, white);
    d.meshes.push_back(make_cube({-kBoxHalf, -kBoxHalf, 0}, {kBoxHalf, kBoxHalf, 2 * kBoxHalf},
                                 Facing::kOutward, white));
    d.lights.push_back(point_light({0, 0, 1}, glm::vec3(1.0f)));
    scene = build_scene(d);
    tracer = std::make_unique<RayTracer>(scene);
    for (int i = 0; i < 40; ++i) {
      for (int j = 0; j < 40; ++j) {
        SurfaceSample s;
        s.center = {-0.975f + 0.05f * float(i), -0.975f + 0.05f * float(j), 0.0f};
        s.normal = {0, 0, 1};
        s.radius = 0.035f;
        s.area = 0.0025f;
        const bool hidden = std::abs(s.center.x) < kBoxHalf && std::abs(s.center.y) < kBoxHalf;
        s.value = glm::vec3(hidden ? 0.0f : 1.0f);
        samples.push_back(s);
      }
    }
  }
  Scene scene;
  std::unique_ptr<RayTracer> tracer;
  std::vector<SurfaceSample> samples;
};

TEST(AntiradianceSplatVisibility, FloorPointsBesideABoxIgnoreTheFloorUnderIt) {
  const FloorWithBox f;
  const SurfaceInterpolation seeing(f.samples, f.tracer.get());
  const SurfaceInterpolation blind(f.samples);
  const glm::vec3 up(0, 0, 1);
  // The support reaches about two sample spacings (0.1 m), so points within it of the box's
  // side mix both kinds without the test.
  for (const float offset : {0.002f, 0.02f, 0.05f}) {
    SCOPED_TRACE(offset);
    const glm::vec3 outside(kBoxHalf + offset, 0.013f, 0.0f),
        inside(kBoxHalf - offset, 0.013f, 0.0f);
    // Every sample these points see has one value: exact.
    EXPECT_FLOAT_EQ(seeing.evaluate(outside, up).x, 1.0f);
    EXPECT_FLOAT_EQ(seeing.evaluate(inside, up).x, 0.0f);
    EXPECT_LT(blind.evaluate(outside, up).x, 0.99f);
    EXPECT_GT(blind.evaluate(inside, up).x, 0.01f);
  }
  // Far from the box nothing is blocked: both agree.
  const glm::vec3 far(-0.7f, 0.6f, 0.0f);
  EXPECT_FLOAT_EQ(seeing.evaluate(far, up).x, blind.evaluate(far, up).x);
}

TEST(AntiradianceSplatVisibility, CurvedSurfacesKeepEveryNeighbour) {
  // An outward icosphere of 0.5 m (1280 facets, about 0.05 m each) with one sample per facet
  // whose value is its height: convex, so the straight segment between a point and a
  // neighbour's center dips under the facets unless lifted (the lift's reason), and the
  // visibility test must leave the interpolation exactly as it is without it.
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.5f));
  d.meshes.push_back(make_icosphere({0, 0, 0}, 0.5f, 3, white));
  d.lights.push_back(point_light({0, 0, 2}, glm::vec3(1.0f)));
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  std::vector<SurfaceSample> samples;
  for (const Triangle& t : scene.triangles) {
    SurfaceSample s;
    s.center = (t.p[0] + t.p[1] + t.p[2]) / 3.0f;
    s.normal = t.face_normal;
    for (const glm::vec3& p : t.p) s.radius = std::max(s.radius, glm::length(p - s.center));
    s.area = t.area;
    s.value = glm::vec3(s.center.z + 1.0f);
    samples.push_back(s);
  }
  const SurfaceInterpolation seeing(samples, &tracer);
  const SurfaceInterpolation blind(samples);
  for (const glm::vec3& p : scene.description.meshes[0].positions) {
    const glm::vec3 n = glm::normalize(p);
    EXPECT_FLOAT_EQ(seeing.evaluate(p, n).x, blind.evaluate(p, n).x) << p.x << " " << p.y;
  }
}

TEST(AntiradianceSplatVisibility, TwinsNeverBleedIntoTheOtherSide) {
  // A plane's patches and their back-side twins (same centers, opposite normals) with
  // different values: a point reads only its own side, with the tracer or without, also where
  // it falls back to the nearest patch (far off the plane).
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.5f));
  add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, 1, white);
  d.lights.push_back(point_light({0, 0, 1}, glm::vec3(1.0f)));
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  std::vector<SurfaceSample> samples;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      SurfaceSample s;
      s.center = {-0.95f + 0.1f * float(i), -0.95f + 0.1f * float(j), 0.0f};
      s.radius = 0.07f;
      s.area = 0.01f;
      s.normal = {0, 0, 1};
      s.value = glm::vec3(1.0f);
      samples.push_back(s);
      s.normal = {0, 0, -1};
      s.value = glm::vec3(0.25f);
      samples.push_back(s);
    }
  }
  for (const RayTracer* visibility : {static_cast<const RayTracer*>(nullptr), &tracer}) {
    const SurfaceInterpolation splat(samples, visibility);
    for (const glm::vec3& p : {glm::vec3(0.13f, -0.41f, 0.0f), glm::vec3(0.99f, 0.99f, 0.0f),
                               glm::vec3(0.0f, 0.0f, 5.0f)}) {
      EXPECT_FLOAT_EQ(splat.evaluate(p, {0, 0, 1}).x, 1.0f);
      EXPECT_FLOAT_EQ(splat.evaluate(p, {0, 0, -1}).x, 0.25f);
    }
  }
}

}  // namespace
}  // namespace bakegi::test
