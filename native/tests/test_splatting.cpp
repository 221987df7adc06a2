// The splatting method (Nichols & Wyman 2009; issue 17): reflective shadow maps carry the
// lights' exact power, VPL light matches analytic one-bounce cases, the min-max mipmap and
// refinement split where the paper says, the upsampling keeps smooth light and never spreads
// it into empty texels, and multiresolution splatting matches full-resolution splatting.
#include <gtest/gtest.h>

#include <cmath>

#include "light_transport_fixtures.h"
#include "lights/direct_light.h"
#include "scene/phong_lobe.h"
#include "solvers/splatting/eye_gbuffer.h"
#include "solvers/splatting/glossy_receivers.h"
#include "solvers/splatting/min_max_mipmap.h"
#include "solvers/splatting/multiresolution_buffer.h"
#include "solvers/splatting/near_field_gather.h"
#include "solvers/splatting/reflective_shadow_map.h"
#include "solvers/splatting/splatting_indirect.h"
#include "solvers/splatting/splatting_preview.h"
#include "solvers/splatting/subsplat_refinement.h"
#include "solvers/splatting/virtual_point_lights.h"
#include "solvers/splatting/vpl_visibility.h"
#include "util/luminance.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

using test::add_material;
using test::Facing;
using test::make_cube;
using test::make_icosphere;

constexpr double kPiD = 3.14159265358979323846;

struct BuiltScene {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<RayTracer> tracer;
  explicit BuiltScene(const SceneDescription& d)
      : scene(std::make_unique<Scene>(build_scene(d))),
        tracer(std::make_unique<RayTracer>(*scene)) {}
};

SceneDescription room_with(const Light& light, float albedo = 0.5f) {
  SceneDescription d;
  const uint32_t m = add_material(d, glm::vec3(albedo));
  d.meshes.push_back(make_cube({-1, -1, -1}, {1, 1, 1}, Facing::kInward, m));
  d.lights.push_back(light);
  return d;
}

// Every texel's ray lands inside a closed room: the reflected flux is albedo x the light's
// power, whatever the map kind (exact per texel, so only float rounding remains).
TEST(SplattingRsm, ClosedRoomReflectsAlbedoTimesPower) {
  const BuiltScene point(room_with(test::point_light({0.1f, 0.2f, -0.3f}, glm::vec3(10.0f))));
  RsmOptions options;
  options.resolution = 64;
  const glm::dvec3 reflected =
      total_reflected_flux(render_reflective_shadow_maps(*point.scene, *point.tracer, options));
  // The cube map's texels cover the sphere of directions: 4 pi sr.
  EXPECT_NEAR(reflected.x, 0.5 * 4.0 * kPiD * 10.0, 1e-3 * 0.5 * 4.0 * kPiD * 10.0);

  const Light area = test::area_light(BAKEGI_AREA_RECTANGLE, {0, 0, 0.9f}, {0, 0, -1}, {1, 0, 0},
                                      0.5f, 0.25f, glm::vec3(4.0f));
  const BuiltScene lit(room_with(area));
  const glm::dvec3 area_flux =
      total_reflected_flux(render_reflective_shadow_maps(*lit.scene, *lit.tracer, options));
  const double power = kPiD * 4.0 * 0.5 * 0.25;  // pi L A of a one-sided Lambertian emitter
  EXPECT_NEAR(area_flux.x, 0.5 * power, 1e-3 * 0.5 * power);
}

// A sun over a floor: the floor intercepts S cos(theta) times its area.
TEST(SplattingRsm, SunOnAFloorReflectsItsIrradianceTimesArea) {
  SceneDescription d;
  const uint32_t m = add_material(d, glm::vec3(0.8f));
  test::add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 2.0f, 1.5f, m);
  Light sun;
  sun.type = BAKEGI_LIGHT_SUN;
  sun.direction = glm::normalize(glm::vec3(0.3f, 0.0f, -1.0f));
  sun.color = glm::vec3(3.0f);
  d.lights.push_back(sun);
  const BuiltScene built(d);
  RsmOptions options;
  options.resolution = 256;
  const glm::dvec3 flux =
      total_reflected_flux(render_reflective_shadow_maps(*built.scene, *built.tracer, options));
  const double expected = 0.8 * 3.0 * double(-sun.direction.z) * (4.0 * 3.0);
  // Texels straddling the floor's edge: about the perimeter's share of the texels.
  EXPECT_NEAR(flux.x, expected, 0.02 * expected);
}

// Inside a sphere every pair of points sees each other with cos cos / r^2 = 1 / (4 R^2), so
// one bounce from a light at the centre is uniform: E = rho I / R^2, value E / pi.
TEST(SplattingVpls, SphereRoomOneBounceIsAnalytic) {
  SceneDescription d;
  const uint32_t m = add_material(d, glm::vec3(0.6f));
  d.meshes.push_back(make_icosphere({0, 0, 0}, 1.0f, 4, m));
  d.lights.push_back(test::point_light({0, 0, 0}, glm::vec3(5.0f)));
  const BuiltScene built(d);
  RsmOptions options;
  options.resolution = 128;
  const auto maps = render_reflective_shadow_maps(*built.scene, *built.tracer, options);
  const double expected = 0.6 * 5.0 / kPiD;
  for (VplSampling sampling : {VplSampling::kRegular, VplSampling::kImportance}) {
    const VirtualPointLights vpls = select_vpls(maps, 1024, sampling);
    ASSERT_GE(vpls.size(), 990u);
    glm::dvec3 total(0.0);
    for (const glm::vec3& f : vpls.fluxes) total += glm::dvec3(f);
    EXPECT_NEAR(total.x, 0.6 * 4.0 * kPiD * 5.0, 1e-3 * 0.6 * 4.0 * kPiD * 5.0);
    for (const glm::vec3& p :
         {glm::vec3(0, 0, -1), glm::vec3(0.6f, 0.0f, 0.8f), glm::normalize(glm::vec3(1, 1, 1))}) {
      // A point just inside the tessellated sphere, facing the centre.
      const glm::vec3 value = vpl_irradiance_over_pi(vpls, p * 0.995f, -p);
      // Flat triangles and the near-field bound of the closest VPLs: a few percent.
      EXPECT_NEAR(value.x, expected, 0.04 * expected) << "at " << p.x << "," << p.y << "," << p.z;
    }
  }
}

// A synthetic G-buffer: a plane facing the eye at depth 1 on the left of column `edge` and at
// depth 2 on its right.
EyeGBuffer step_gbuffer(uint32_t width, uint32_t height, uint32_t edge) {
  EyeGBuffer g;
  g.width = width;
  g.height = height;
  const size_t n = g.size();
  g.hit.assign(n, 1);
  g.depth.assign(n, 1.0f);
  g.position.assign(n, glm::vec3(0.0f));
  g.normal.assign(n, glm::vec3(0, 0, 1));
  g.geometric = g.normal;
  g.albedo.assign(n, glm::vec3(0.5f));
  g.emission.assign(n, glm::vec3(0.0f));
  g.view = g.normal;
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = g.index(x, y);
      g.depth[i] = x < edge ? 1.0f : 2.0f;
      g.position[i] = glm::vec3(float(x), float(y), -g.depth[i]);
    }
  }
  return g;
}

uint32_t level_at(const SubsplatSet& set, uint32_t x, uint32_t y) {
  for (const Subsplat& s : set.subsplats) {
    const uint32_t cell = 1u << s.level;
    if (x / cell == s.x && y / cell == s.y) return s.level;
  }
  return 255;
}

// Refinement splits down to pixels along a depth edge and leaves the rest coarse; every
// pixel is covered by exactly one subsplat.
TEST(SplattingRefinement, SplitsAtDiscontinuitiesAndCoversEveryPixelOnce) {
  const EyeGBuffer g = step_gbuffer(64, 64, 37);  // the edge inside a 16-pixel texel
  DiscontinuityTest test;
  const MinMaxMipmap mipmap(g, 4, test);
  const SubsplatSet set = refine_subsplats(mipmap, 4, 0, test);
  std::vector<int> covered(g.size(), 0);
  for (const Subsplat& s : set.subsplats) {
    const uint32_t cell = 1u << s.level;
    for (uint32_t y = s.y * cell; y < (s.y + 1) * cell; ++y) {
      for (uint32_t x = s.x * cell; x < (s.x + 1) * cell; ++x) ++covered[g.index(x, y)];
    }
  }
  for (int c : covered) ASSERT_EQ(c, 1);
  EXPECT_EQ(level_at(set, 36, 10), 0u);
  EXPECT_EQ(level_at(set, 37, 10), 0u);
  EXPECT_EQ(level_at(set, 2, 10), 4u);
  // Texels diagonal to a discontinuous one split too (the paper's §5.2 fix): the right
  // column's texels are next to the edge's column; without that rule they stay whole.
  EXPECT_EQ(level_at(set, 60, 60), 3u);
  DiscontinuityTest own = test;
  own.neighbours = NeighbourTest::kNone;
  EXPECT_EQ(level_at(refine_subsplats(MinMaxMipmap(g, 4, own), 4, 0, own), 60, 60), 4u);
  EXPECT_LT(set.subsplats.size(), g.size() / 6);
}

// An edge on a texel boundary is invisible to each texel's own min and max (the paper's
// Fig. 15, top); testing the texel with its eight neighbours finds it.
TEST(SplattingRefinement, EdgesOnTexelBoundariesNeedTheNeighbourTest) {
  const EyeGBuffer g = step_gbuffer(64, 64, 32);
  DiscontinuityTest own;
  own.neighbours = NeighbourTest::kNone;
  const SubsplatSet missed = refine_subsplats(MinMaxMipmap(g, 4, own), 4, 0, own);
  EXPECT_EQ(level_at(missed, 31, 20), 4u);
  DiscontinuityTest all;
  all.neighbours = NeighbourTest::kAll;
  const SubsplatSet found = refine_subsplats(MinMaxMipmap(g, 4, all), 4, 0, all);
  EXPECT_EQ(level_at(found, 31, 20), 0u);
  EXPECT_EQ(level_at(found, 32, 20), 0u);
}

// Interpolated upsampling reproduces constant light exactly whatever the levels, and never
// puts light where no subsplat was.
TEST(SplattingUpsampling, KeepsConstantLightAndLeavesEmptyTexelsEmpty) {
  const EyeGBuffer g = step_gbuffer(64, 64, 37);
  DiscontinuityTest test;
  const MinMaxMipmap mipmap(g, 4, test);
  const SubsplatSet set = refine_subsplats(mipmap, 4, 0, test);
  MultiresolutionBuffer buffer(64, 64, mipmap.levels());
  // Light only on the left of the edge (the subsplats whose pixels are all at depth 1).
  for (const Subsplat& s : set.subsplats) {
    const uint32_t cell = 1u << s.level;
    if ((s.x + 1) * cell <= 37) buffer.add(s, glm::vec3(2.0f, 1.0f, 0.5f));
  }
  const std::vector<glm::vec3> image = buffer.upsample(Upsampling::kInterpolated);
  for (uint32_t y = 0; y < 64; ++y) {
    for (uint32_t x = 0; x < 64; ++x) {
      const glm::vec3 v = image[g.index(x, y)];
      if (x < 37) {
        EXPECT_NEAR(v.x, 2.0f, 1e-5f) << x << "," << y;
        EXPECT_NEAR(v.z, 0.5f, 1e-5f);
      } else {
        EXPECT_EQ(v.x, 0.0f) << x << "," << y;  // no light spread across the edge
      }
    }
  }
}

// A plane seen straight on, tilted in depth along x (continuous everywhere).
EyeGBuffer plane_gbuffer(uint32_t width, uint32_t height) {
  EyeGBuffer g = step_gbuffer(width, height, width);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = g.index(x, y);
      g.depth[i] = 1.0f + 0.001f * float(x);
      g.position[i] = glm::vec3(float(x), float(y), -g.depth[i]);
    }
  }
  return g;
}

// A subsplat stands for its texel's centre, so it must read the surface there: between the
// four middle pixels of a texel of 8, not at any one pixel (half a pixel off at best; the
// children's representatives alone drift 1.5 pixels).
TEST(SplattingMipmap, SubsplatsReadTheSurfaceAtTheirTexelCentre) {
  const EyeGBuffer g = plane_gbuffer(64, 64);
  DiscontinuityTest test;
  const MinMaxMipmap mipmap(g, 4, test);
  const MipLevel& l = mipmap.level(3);
  EXPECT_EQ(l.representative[l.index(1, 2)], g.index(12, 20));  // the pixel at the centre
  const SurfacePoint p = mipmap.point(g, 3, 1, 2, test);
  EXPECT_NEAR(p.position.x, 11.5f, 1e-5f);
  EXPECT_NEAR(p.position.y, 19.5f, 1e-5f);
  EXPECT_NEAR(p.shading_normal.z, 1.0f, 1e-6f);
  const SurfacePoint pixel = mipmap.point(g, 0, 5, 7, test);
  EXPECT_EQ(pixel.position, g.position[g.index(5, 7)]);
}

// Light that changes linearly across a surface is what bilinear interpolation reproduces
// exactly: with every subsplat at the coarsest level, the upsampled image equals the light
// at every pixel, the border's too (the neighbour beyond the image is extrapolated).
TEST(SplattingUpsampling, ReproducesLinearLightFromCoarseSubsplats) {
  const EyeGBuffer g = plane_gbuffer(64, 64);
  DiscontinuityTest test;
  const MinMaxMipmap mipmap(g, 4, test);
  const SubsplatSet set = refine_subsplats(mipmap, 4, 0, test);
  ASSERT_EQ(set.per_level[4], set.subsplats.size());  // nothing to refine on a plane
  const auto linear = [](const glm::vec3& p) { return 1.0f + 0.02f * p.x + 0.05f * p.y; };
  MultiresolutionBuffer buffer(64, 64, mipmap.levels());
  render_subsplats(
      set, mipmap, g, test, [&](const SurfacePoint& p) { return glm::vec3(linear(p.position)); },
      buffer);
  const std::vector<glm::vec3> image = buffer.upsample(Upsampling::kInterpolated);
  for (uint32_t y = 0; y < 64; ++y) {
    for (uint32_t x = 0; x < 64; ++x) {
      ASSERT_NEAR(image[g.index(x, y)].x, linear(g.position[g.index(x, y)]), 1e-4f)
          << x << "," << y;
    }
  }
}

SceneDescription lit_room() {
  SceneDescription d;
  const uint32_t white = add_material(d, glm::vec3(0.7f));
  const uint32_t red = add_material(d, glm::vec3(0.8f, 0.1f, 0.1f));
  d.meshes.push_back(make_cube({-2, -2, 0}, {2, 2, 3}, Facing::kInward, white));
  d.meshes.push_back(make_cube({-0.8f, -0.2f, 0}, {0.2f, 0.8f, 1.2f}, Facing::kOutward, red));
  d.lights.push_back(test::point_light({0.5f, -0.5f, 2.5f}, glm::vec3(20.0f)));
  return d;
}

PreviewCamera room_camera() {
  PreviewCamera c;
  c.position = {0.0f, -1.9f, 1.5f};
  c.forward = glm::normalize(glm::vec3(0.0f, 1.0f, -0.15f));
  c.up = {0, 0, 1};
  c.fov_y = 1.2f;
  return c;
}

double luminance_nrmse(const std::vector<glm::vec3>& y, const std::vector<glm::vec3>& r) {
  double sum = 0.0, mean = 0.0;
  for (size_t i = 0; i < y.size(); ++i) {
    const double d = luminance(y[i]) - luminance(r[i]);
    sum += d * d;
    mean += luminance(r[i]);
  }
  mean /= double(y.size());
  return std::sqrt(sum / double(y.size())) / mean;
}

// The claim shape: multiresolution splatting gives full-resolution splatting's image
// within a few percent from a fraction of the subsplats.
TEST(SplattingPreview, MultiresolutionMatchesFullResolution) {
  SplattingPreview preview(lit_room());
  SplattingSettings settings;
  settings.direct_samples = 0;
  settings.near_field_split = 0.0f;
  const PreviewFrame multi = preview.render(room_camera(), 200, 150, settings);
  settings.refinement = SubsplatRefinement::kNone;
  const PreviewFrame full = preview.render(room_camera(), 200, 150, settings);
  EXPECT_TRUE(full.statistics.gbuffer_reused);
  const double nrmse = luminance_nrmse(multi.indirect, full.indirect);
  EXPECT_LT(nrmse, 0.03);
  EXPECT_GT(nrmse, 0.0);
  EXPECT_LT(multi.statistics.splat.subsplats * 3, full.statistics.splat.subsplats);
  for (const glm::vec3& v : multi.indirect) {
    ASSERT_TRUE(std::isfinite(v.x) && v.x >= 0.0f);
  }
}

// While the camera stays, a frame keeps the min-max mipmap and the buffer's memory: the
// same image as a first frame, bit for bit; a moved camera rebuilds them.
TEST(SplattingPreview, KeepsTheMipmapWhileTheCameraStays) {
  SplattingPreview preview(lit_room());
  SplattingSettings settings;
  settings.direct_samples = 0;
  const PreviewFrame first = preview.render(room_camera(), 80, 60, settings);
  EXPECT_FALSE(first.statistics.splat.mipmap_reused);
  const PreviewFrame again = preview.render(room_camera(), 80, 60, settings);
  EXPECT_TRUE(again.statistics.splat.mipmap_reused);
  ASSERT_EQ(again.indirect.size(), first.indirect.size());
  for (size_t i = 0; i < first.indirect.size(); ++i)
    ASSERT_EQ(again.indirect[i], first.indirect[i]);
  PreviewCamera moved = room_camera();
  moved.position.x += 0.3f;
  EXPECT_FALSE(preview.render(moved, 80, 60, settings).statistics.splat.mipmap_reused);
  settings.discontinuity.normal = NormalTest::kCurvature;  // another mipmap
  EXPECT_FALSE(preview.render(moved, 80, 60, settings).statistics.splat.mipmap_reused);
}

// Moving the light moves the bounce; a scene without lights gives black indirect light.
TEST(SplattingPreview, FollowsTheLightsAndSurvivesNone) {
  SplattingPreview preview(lit_room());
  SplattingSettings settings;
  const PreviewFrame before = preview.render(room_camera(), 64, 48, settings);
  std::vector<Light> lights = preview.scene().description.lights;
  lights[0].position.x = -1.5f;
  preview.set_lights(lights, glm::vec3(0.0f));
  const PreviewFrame after = preview.render(room_camera(), 64, 48, settings);
  EXPECT_GT(luminance_nrmse(after.indirect, before.indirect), 0.05);
  preview.set_lights({}, glm::vec3(0.0f));
  const PreviewFrame dark = preview.render(room_camera(), 64, 48, settings);
  EXPECT_EQ(dark.statistics.vpls, 0u);
  for (const glm::vec3& v : dark.indirect) ASSERT_EQ(v.x, 0.0f);
}

// A Phong lobe of exponent 0 is ρ_g/π wherever its mirror axis lies within 90° of the light;
// seen along the normal that is the whole hemisphere, so it reflects irradiance / π.
TEST(SplattingGlossy, AFlatLobeSeenAlongTheNormalReflectsTheIrradiance) {
  VirtualPointLights vpls;
  RandomStream rng(sample_pcg(5, 0, 0));
  for (int v = 0; v < 64; ++v) {
    const glm::vec3 p(rng.next_float() * 4 - 2, rng.next_float() * 4 - 2, 0.2f + rng.next_float());
    vpls.push(p, glm::normalize(glm::vec3(0.1f, 0.0f, -1.0f)), glm::vec3(rng.next_float()), 0.01f);
  }
  const glm::vec3 x(0.1f, -0.2f, 0.0f), n(0, 0, 1);
  const glm::vec3 glossy = vpl_glossy_reflection(vpls, x, n, n, 0.0f);
  const glm::vec3 diffuse = vpl_irradiance_over_pi(vpls, x, n);
  EXPECT_NEAR(glossy.x, diffuse.x, 1e-5f * diffuse.x);
  // A sharp lobe keeps only the VPLs near the mirror direction.
  EXPECT_LT(
      luminance(vpl_glossy_reflection(vpls, x, n, glm::normalize(glm::vec3(1, 0, 0.05f)), 1000.0f)),
      1e-3 * luminance(diffuse));
}

// A near mirror reflects a VPL through a lobe widened to the VPL's own extent (virtual
// spherical lights): the exponent 2 r^2 / a - 1 instead of a spike of (n + 2) / (2 pi).
TEST(SplattingGlossy, AMirrorSeesAVplAsWideAsItsDisk) {
  VirtualPointLights vpls;
  const float a = 0.01f;  // disk area / pi
  vpls.push(glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1.0f), a * kPi);
  const glm::vec3 x(0.0f), n(0, 0, 1);
  const float widest = 2.0f * 1.0f / a - 1.0f;  // 199
  const float e = 1.0f / (kPi * (1.0f + a));    // the VPL's irradiance per unit flux
  const glm::vec3 on_axis = vpl_glossy_reflection(vpls, x, n, n, 10000.0f);
  EXPECT_NEAR(on_axis.x, PhongLobe{widest}.value(1.0f) * e, 1e-4f);
  // 0.05 rad off the mirror direction: outside the exponent-10000 lobe, inside the widened.
  const glm::vec3 tilted = glm::normalize(glm::vec3(std::sin(0.05f), 0.0f, std::cos(0.05f)));
  const glm::vec3 off_axis = vpl_glossy_reflection(vpls, x, n, tilted, 10000.0f);
  EXPECT_NEAR(off_axis.x, PhongLobe{widest}.value(std::cos(0.05f)) * e, 1e-4f);
  EXPECT_GT(off_axis.x, 0.5f * on_axis.x);
  // A lobe already wider than the disk is left as it is.
  EXPECT_NEAR(vpl_glossy_reflection(vpls, x, n, n, 20.0f).x, PhongLobe{20.0f}.value(1.0f) * e,
              1e-5f);
}

// Direct light on a glossy floor: one point light, so light sampling is exact and the lobe's
// ray never meets the lamp; the pixel's glossy radiance is f_g toward the lamp times its
// irradiance. A diffuse wall reflects none.
TEST(SplattingGlossy, DirectLightThroughTheLobeIsFTimesTheIrradiance) {
  SceneDescription d;
  const uint32_t floor = add_material(d, glm::vec3(0.2f));
  d.materials[floor].glossy = glm::vec3(0.5f, 0.4f, 0.3f);
  d.materials[floor].glossy_exponent = 20.0f;
  const uint32_t wall = add_material(d, glm::vec3(0.6f));
  test::add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 4.0f, 4.0f, floor);
  test::add_quad(d, {0, 3, 1}, {1, 0, 0}, {0, 0, 1}, 4.0f, 1.0f, wall);
  d.lights.push_back(test::point_light({0.3f, 0.8f, 1.5f}, glm::vec3(10.0f)));
  const BuiltScene built(d);
  PreviewCamera camera;
  camera.position = {0.0f, -2.0f, 1.5f};
  camera.forward = glm::normalize(glm::vec3(0.0f, 1.0f, -0.45f));
  camera.up = {0, 0, 1};
  const EyeGBuffer g = trace_eye_gbuffer(*built.scene, *built.tracer, camera, 48, 36);
  const DirectLight direct(*built.scene, *built.tracer);
  std::vector<glm::vec3> reflected;
  const uint64_t glossy_pixels =
      glossy_reflection(g, direct, VirtualPointLights(), 1, 3, 0.0f, reflected);
  EXPECT_GT(glossy_pixels, 100u);
  const PhongLobe lobe{20.0f};
  int checked = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    if (!g.hit[i]) continue;
    if (max_component(g.glossy[i]) == 0.0f) {
      ASSERT_EQ(reflected[i], glm::vec3(0.0f));
      continue;
    }
    const SurfacePoint x{g.position[i], g.normal[i], g.geometric[i]};
    RandomStream rng(sample_pcg(0, i, 0));
    uint64_t rays = 0;
    const glm::vec3 irradiance = direct.lamp_irradiance(x, rng, rays);
    const glm::vec3 to_light = glm::normalize(glm::vec3(0.3f, 0.8f, 1.5f) - x.position);
    const glm::vec3 axis = mirror_direction(x.shading_normal, g.view[i]);
    const glm::vec3 expected = g.glossy[i] * lobe.value(glm::dot(axis, to_light)) * irradiance;
    ASSERT_NEAR(reflected[i].x, expected.x, 1e-4f * (1.0f + expected.x)) << i;
    ASSERT_NEAR(reflected[i].z, expected.z, 1e-4f * (1.0f + expected.z)) << i;
    checked += expected.x > 1e-3f;
  }
  EXPECT_GT(checked, 50);  // the highlight is in view
}

// The preview adds the glossy reflection to the frame, and only on glossy surfaces.
TEST(SplattingGlossy, ThePreviewAddsTheLobeToGlossyPixelsOnly) {
  SceneDescription d = lit_room();
  d.materials[1].glossy = glm::vec3(0.15f);  // the red box
  d.materials[1].glossy_exponent = 50.0f;
  SplattingPreview preview(d);
  SplattingSettings settings;
  const PreviewFrame frame = preview.render(room_camera(), 80, 60, settings);
  EXPECT_GT(frame.statistics.glossy_pixels, 0u);
  double lobe = 0.0;
  uint64_t seen = 0, lit = 0;
  for (size_t i = 0; i < frame.combined.size(); ++i) {
    if (!frame.seen[i]) continue;
    ++seen;
    lit += max_component(frame.glossy[i]) > 0.0f;
    lobe += luminance(frame.glossy[i]);
  }
  EXPECT_GT(lobe, 0.0);
  EXPECT_LE(lit, frame.statistics.glossy_pixels);
  EXPECT_LT(frame.statistics.glossy_pixels, seen / 2);  // the walls stay diffuse
  // A wide lobe (a Principled coat's exponent 7.5) folds into the albedo: nothing gathered,
  // the diffuse light brighter by its hemispherical albedo times rho_g.
  d.materials[1].glossy_exponent = 7.5f;
  SplattingPreview folded(d);
  const PreviewFrame wide = folded.render(room_camera(), 80, 60, settings);
  EXPECT_EQ(wide.statistics.glossy_pixels, 0u);
  const EyeGBuffer g =
      trace_eye_gbuffer(folded.scene(), RayTracer(folded.scene()), room_camera(), 80, 60);
  std::vector<glm::vec3> albedo;
  folded_albedo(g, settings.glossy_fold_exponent, albedo);
  const float fold = float(phong_hemispherical_albedo(7.5));
  int box = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    if (max_component(g.glossy[i]) == 0.0f) {
      ASSERT_EQ(albedo[i], g.albedo[i]);
      continue;
    }
    ++box;
    ASSERT_NEAR(albedo[i].x, g.albedo[i].x + fold * 0.15f, 1e-6f);
  }
  EXPECT_GT(box, 0);
}

// The optional visibility removes light that passes through a wall between two rooms.
TEST(SplattingVisibility, ClusteredShadowRaysStopLightThroughAWall) {
  SceneDescription d;
  const uint32_t m = add_material(d, glm::vec3(0.7f));
  d.meshes.push_back(make_cube({-2, -1, 0}, {2, 1, 2}, Facing::kInward, m));
  test::add_quad(d, {0, 0, 1}, {0, 1, 0}, {0, 0, 1}, 1.0f, 1.0f, m);  // the wall at x = 0
  d.lights.push_back(test::point_light({-1.0f, 0.0f, 1.0f}, glm::vec3(10.0f)));
  const BuiltScene built(d);
  RsmOptions options;
  VirtualPointLights vpls =
      select_vpls(render_reflective_shadow_maps(*built.scene, *built.tracer, options), 256,
                  VplSampling::kRegular);
  // A point in the dark room facing the wall's other side, and the ceiling there.
  const glm::vec3 p(1.9f, 0.0f, 1.0f), n(-1, 0, 0);
  const glm::vec3 leak = vpl_irradiance_over_pi(vpls, p, n);
  EXPECT_GT(leak.x, 0.0f);  // the paper's VPL light passes the wall
  const VplClusters clusters = cluster_vpls(vpls, 64);
  uint64_t rays = 0;
  const glm::vec3 seen = visible_vpl_light(
      clusters, *built.tracer, 1e-4f, p, n,
      [&](size_t begin, size_t end) { return vpl_irradiance_over_pi(vpls, p, n, begin, end); },
      rays);
  EXPECT_GT(rays, 0u);
  EXPECT_LT(seen.x, 0.05f * leak.x);
}

// The bake method over points (the point hierarchy) on the sphere room: the analytic one
// bounce at points spread over the sphere, coarse subsplats and single points alike.
TEST(SplattingBake, SphereRoomPointsGetTheAnalyticBounce) {
  SceneDescription d;
  const uint32_t m = add_material(d, glm::vec3(0.6f));
  d.meshes.push_back(make_icosphere({0, 0, 0}, 1.0f, 4, m));
  d.lights.push_back(test::point_light({0, 0, 0}, glm::vec3(5.0f)));
  std::vector<glm::vec3> positions, normals;
  for (const glm::vec3& v : d.meshes[0].positions) {
    positions.push_back(v * 0.999f);
    normals.push_back(-glm::normalize(v));
  }
  test::Baker baker(d);
  test::BakeOptions options;
  options.method = "splatting";
  const std::vector<glm::vec3> values = baker.bake(test::make_points(positions, normals), options);
  const double expected = 0.6 * 5.0 / kPiD;
  double sum = 0.0;
  for (const glm::vec3& v : values) {
    ASSERT_NEAR(v.x, expected, 0.06 * expected);
    sum += v.x;
  }
  EXPECT_NEAR(sum / double(values.size()), expected, 0.02 * expected);
}

// The preview's direct light (light sampling alone, one ray a light) estimates the same
// irradiance as the bakes' MIS estimate, for an area light seen at a grazing angle too.
TEST(SplattingDirect, LampIrradianceAgreesWithTheMisEstimate) {
  const Light area = test::area_light(BAKEGI_AREA_RECTANGLE, {0, 0, 0.9f}, {0, 0, -1}, {1, 0, 0},
                                      0.5f, 0.25f, glm::vec3(4.0f));
  const BuiltScene built(room_with(area));
  const DirectLight direct(*built.scene, *built.tracer);
  for (const SurfacePoint& x : {SurfacePoint{{0.2f, 0.1f, -0.999f}, {0, 0, 1}, {0, 0, 1}},
                                SurfacePoint{{-0.999f, 0.3f, 0.7f}, {1, 0, 0}, {1, 0, 0}}}) {
    double lamp = 0.0, mis = 0.0;
    uint64_t rays = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      RandomStream a(sample_pcg(1, 0, uint64_t(i))), b(sample_pcg(2, 0, uint64_t(i)));
      lamp += direct.lamp_irradiance(x, a, rays).x;
      mis += direct.irradiance_sample(x, b, rays).x;
    }
    EXPECT_NEAR(lamp / n, mis / n, 0.02 * mis / n);
  }
}

// Bias compensation is unbiased: in the sphere room (G = 1 / (4 R^2) between any two points)
// with the clamp well below G, the clamped VPLs carry b / G of the bounce and the gather rays
// the rest; together the analytic one bounce.
TEST(SplattingGather, ClampedVplsPlusGatherRaysGiveTheAnalyticBounce) {
  SceneDescription d;
  const uint32_t m = add_material(d, glm::vec3(0.6f));
  d.meshes.push_back(make_icosphere({0, 0, 0}, 1.0f, 4, m));
  d.lights.push_back(test::point_light({0, 0, 0}, glm::vec3(5.0f)));
  const BuiltScene built(d);
  const DirectLight direct(*built.scene, *built.tracer);
  const VirtualPointLights vpls =
      select_vpls(render_reflective_shadow_maps(*built.scene, *built.tracer, RsmOptions{}), 1024,
                  VplSampling::kRegular);
  const float bound = 0.1f;  // G = 0.25 everywhere: 40% by the VPLs, 60% by the rays
  const double expected = 0.6 * 5.0 / kPiD;
  const glm::vec3 p = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f)) * 0.995f;
  const glm::vec3 n = -glm::normalize(p);
  const glm::vec3 clamped = clamped_vpl_light(vpls, p, n, 0, vpls.size(), bound);
  uint64_t traced = 0;
  EXPECT_NEAR(clamped.x, expected * 0.4, 0.04 * expected * 0.4);
  const glm::vec3 residual =
      near_field_residual(*built.scene, *built.tracer, direct, p, n, bound, 4096, 1, 0, traced);
  EXPECT_NEAR(clamped.x + residual.x, expected, 0.03 * expected);
  // Where G never reaches the bound the rays add nothing.
  EXPECT_GE(traced, 4096u);
  EXPECT_EQ(
      near_field_residual(*built.scene, *built.tracer, direct, p, n, 1.0f, 64, 1, 0, traced).x,
      0.0f);
}

}  // namespace
}  // namespace bakegi
