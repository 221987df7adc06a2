// build_scene and Scene::albedo_at: what the validated scene holds (normals, lights made
// unit, degenerate triangles dropped) and bilinear, repeating texture lookups.
#include <cmath>

#include <gtest/gtest.h>

#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

// One triangle with uvs equal to its xy coordinates, lit by a point light.
SceneDescription textured_triangle(glm::vec3 albedo) {
  SceneDescription d;
  Texture texture;
  texture.width = 2;
  texture.height = 2;
  // Row 0 (v near 0) first: red, green; row 1: blue, white.
  texture.set_texels({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}});
  d.textures.push_back(texture);
  Material material;
  material.albedo = albedo;
  material.albedo_texture = 0;
  d.materials.push_back(material);
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.indices = {0, 1, 2};
  mesh.corner_uvs = {{0, 0}, {1, 0}, {0, 1}};
  d.meshes.push_back(mesh);
  Light light;
  light.color = glm::vec3(1.0f);
  d.lights.push_back(light);
  return d;
}

void expect_vec_near(glm::vec3 a, glm::vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-6f);
  EXPECT_NEAR(a.y, b.y, 1e-6f);
  EXPECT_NEAR(a.z, b.z, 1e-6f);
}

TEST(SceneBuild, AlbedoTextureIsBilinearRepeatingAndScaled) {
  const Scene scene = build_scene(textured_triangle({0.5f, 0.5f, 0.5f}));
  const Triangle& t = scene.triangles[0];
  // With uv = (x, y), barycentrics (b1, b2) are uv itself.
  auto albedo = [&](float u, float v) { return scene.albedo_at(t, u, v); };
  // Texel centres give the texel times the material albedo.
  expect_vec_near(albedo(0.25f, 0.25f), {0.5f, 0, 0});
  expect_vec_near(albedo(0.75f, 0.25f), {0, 0.5f, 0});
  expect_vec_near(albedo(0.25f, 0.75f), {0, 0, 0.5f});
  // Halfway between the two bottom texel centres: their mean.
  expect_vec_near(albedo(0.5f, 0.25f), {0.25f, 0.25f, 0});
  // The corner uv (0,0) lies between all four texel centres once wrapped: their mean.
  expect_vec_near(albedo(0.0f, 0.0f), {0.25f, 0.25f, 0.25f});
}

TEST(SceneBuild, TextureRepeatsOutsideTheUnitSquare) {
  SceneDescription d = textured_triangle({1, 1, 1});
  d.meshes[0].corner_uvs = {{3.25f, -1.75f}, {4.25f, -1.75f}, {3.25f, -0.75f}};
  const Scene scene = build_scene(d);
  // uv (3.25, -1.75) wraps to (0.25, 0.25): the red texel's centre.
  expect_vec_near(scene.albedo_at(scene.triangles[0], 0, 0), {1, 0, 0});
  // uv (3.75, -1.25) wraps to (0.75, 0.75): the white texel's centre.
  expect_vec_near(scene.albedo_at(scene.triangles[0], 0.5f, 0.5f), {1, 1, 1});
}

TEST(SceneBuild, NormalsLightsAndBounds) {
  SceneDescription d;
  d.materials.push_back(Material{});
  Mesh mesh;
  mesh.positions = {{0, 0, 1}, {2, 0, 1}, {0, 2, 1}, {1, 0, 1}};
  mesh.indices = {0, 1, 2, 0, 3, 1};  // the second triangle is a line: dropped
  // Given normals: one long, one zero (replaced by the face normal), one tilted.
  mesh.corner_normals = {{0, 0, 5}, {0, 0, 0}, {0, 3, 4}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  d.meshes.push_back(mesh);
  Light area;
  area.type = BAKEGI_LIGHT_AREA;
  area.position = {0.5f, 0.5f, 3.0f};
  area.direction = {0, 0, -2};
  area.axis_u = {2, 0, 1};  // not orthogonal to direction: its projection is used
  area.color = glm::vec3(1.0f);
  area.shape = BAKEGI_AREA_DISK;
  area.size_x = 0.5f;
  d.lights.push_back(area);

  const Scene scene = build_scene(d);
  ASSERT_EQ(scene.triangles.size(), 1u);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_EQ(scene.warnings[0],
            "mesh 0 (object 0): 1 of 2 triangles dropped as degenerate (zero area)");
  const Triangle& t = scene.triangles[0];
  expect_vec_near(t.face_normal, {0, 0, 1});
  EXPECT_FLOAT_EQ(t.area, 2.0f);
  expect_vec_near(t.n[0], {0, 0, 1});
  expect_vec_near(t.n[1], {0, 0, 1});
  expect_vec_near(t.n[2], {0, 0.6f, 0.8f});
  const Light& light = scene.description.lights[0];
  expect_vec_near(light.direction, {0, 0, -1});
  expect_vec_near(light.axis_u, {1, 0, 0});
  EXPECT_EQ(light.size_y, 0.5f);  // a disk is as tall as it is wide
  expect_vec_near(scene.bounds_min, {0, 0, 1});
  expect_vec_near(scene.bounds_max, {2, 2, 1});
  EXPECT_TRUE(scene.emissive_triangles.empty());
}

TEST(SceneBuild, RelitSceneTakesNewLightsAndKeepsTheFlattenedGeometry) {
  const Scene previous = build_scene(textured_triangle({0.5f, 0.5f, 0.5f}));
  SceneDescription changed = textured_triangle({0.5f, 0.5f, 0.5f});
  Light spot;
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.position = {0.2f, 0.2f, 2.0f};
  spot.direction = {0, 0, -3};  // made unit, as build_scene does
  spot.spot_size = 1.0f;
  spot.color = {2.0f, 1.0f, 0.5f};
  changed.lights = {spot};
  changed.world_radiance = {0.1f, 0.1f, 0.1f};

  const Scene relit = build_relit_scene(previous, changed);
  ASSERT_EQ(relit.description.lights.size(), 1u);
  EXPECT_EQ(relit.description.lights[0].type, BAKEGI_LIGHT_SPOT);
  expect_vec_near(relit.description.lights[0].direction, {0, 0, -1});
  expect_vec_near(relit.description.world_radiance, {0.1f, 0.1f, 0.1f});
  // What a full build of the changed description gives.
  const Scene rebuilt = build_scene(changed);
  EXPECT_EQ(relit.description.lights[0].direction, rebuilt.description.lights[0].direction);
  ASSERT_EQ(relit.triangles.size(), rebuilt.triangles.size());
  EXPECT_EQ(relit.triangles[0].p[1], rebuilt.triangles[0].p[1]);
  EXPECT_EQ(relit.triangles[0].area, rebuilt.triangles[0].area);
  EXPECT_EQ(relit.bounds_max, rebuilt.bounds_max);
  EXPECT_EQ(relit.description.textures, rebuilt.description.textures);

  // Lights are still checked: a bad one, or none at all, is refused as in build_scene.
  SceneDescription bad = changed;
  bad.lights[0].color.x = std::nanf("");
  EXPECT_THROW(build_relit_scene(previous, bad), Error);
  SceneDescription dark = changed;
  dark.lights.clear();
  dark.world_radiance = glm::vec3(0.0f);
  EXPECT_THROW(build_relit_scene(previous, dark), Error);
}

}  // namespace
}  // namespace bakegi::test
