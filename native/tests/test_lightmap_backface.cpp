// Rejection of lightmap samples inside geometry: on a floor with a closed box standing in it
// (its bottom below the floor, as objects placed by hand often are), a floor sample under the
// box sees only the box's inside (back faces) and is flagged; samples beside the box, on its
// top, or in the open, are not.
#include <gtest/gtest.h>

#include "lightmap/backface_rejection.h"
#include "scene/scene_validation.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

// Adds the quad centre +- u +- v with outward normal u x v (counter-clockwise seen from it).
void add_quad(Mesh& mesh, glm::vec3 centre, glm::vec3 u, glm::vec3 v) {
  const uint32_t base = uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(),
                        {centre - u - v, centre + u - v, centre + u + v, centre - u + v});
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// Floor [-2,2]^2 at z = 0 (mesh 0) and the box [-0.5,0.5]^2 x [-0.25,0.5] (mesh 1).
Scene floor_and_box() {
  SceneDescription d;
  d.materials.push_back(Material{});
  Light light;
  light.position = {0, 0, 3};
  light.color = glm::vec3(1.0f);
  d.lights.push_back(light);
  Mesh floor;
  add_quad(floor, {0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  Mesh box;
  add_quad(box, {0, 0, 0.5f}, {0.5f, 0, 0}, {0, 0.5f, 0});          // top, +z
  add_quad(box, {0, 0, -0.25f}, {0, 0.5f, 0}, {0.5f, 0, 0});        // bottom, -z
  add_quad(box, {0.5f, 0, 0.125f}, {0, 0.5f, 0}, {0, 0, 0.375f});   // +x
  add_quad(box, {-0.5f, 0, 0.125f}, {0, 0, 0.375f}, {0, 0.5f, 0});  // -x
  add_quad(box, {0, 0.5f, 0.125f}, {0, 0, 0.375f}, {0.5f, 0, 0});   // +y
  add_quad(box, {0, -0.5f, 0.125f}, {0.5f, 0, 0}, {0, 0, 0.375f});  // -y
  d.meshes = {floor, box};
  return build_scene(d);
}

TEST(LightmapBackface, FloorUnderABoxIsRejectedBesideItIsNot) {
  const Scene scene = floor_and_box();
  const RayTracer tracer(scene);
  const std::vector<glm::vec3> positions = {
      {0, 0, 0},         // under the box's centre
      {0.45f, 0.4f, 0},  // under the box, near its corner
      {0.6f, 0, 0},      // beside the box (0.1 from its side)
      {1.5f, 1.5f, 0},   // open floor
      {0, 0, 0.5f},      // on the box's top
  };
  const std::vector<glm::vec3> normals(positions.size(), glm::vec3(0, 0, 1));
  const std::vector<uint8_t> flags =
      flag_samples_inside_geometry(scene, tracer, positions, normals, normals);
  EXPECT_EQ(flags, (std::vector<uint8_t>{1, 1, 0, 0, 0}));

  // The same floor point with only a short reach: the box's inside (>= 0.5 away) is out of
  // range under its centre, but not near its corner.
  BackfaceRejectionOptions near;
  near.max_distance = 0.2f;
  const std::vector<uint8_t> near_flags =
      flag_samples_inside_geometry(scene, tracer, positions, normals, normals, near);
  EXPECT_EQ(near_flags, (std::vector<uint8_t>{0, 1, 0, 0, 0}));
}

TEST(LightmapBackface, RejectsBadOptions) {
  const Scene scene = floor_and_box();
  const RayTracer tracer(scene);
  const std::vector<glm::vec3> p = {{0, 0, 0}}, n = {{0, 0, 1}};
  BackfaceRejectionOptions bad;
  bad.rays = 0;
  EXPECT_THROW(flag_samples_inside_geometry(scene, tracer, p, n, n, bad), Error);
  bad = {};
  bad.backface_fraction = 0;
  EXPECT_THROW(flag_samples_inside_geometry(scene, tracer, p, n, n, bad), Error);
  bad = {};
  bad.max_distance = -1;
  EXPECT_THROW(flag_samples_inside_geometry(scene, tracer, p, n, n, bad), Error);
}

}  // namespace
}  // namespace bakegi::test
