// Every invalid input of the C API gets its specific status and a message that names what
// was wrong; nothing throws or aborts.
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "api/handles.h"
#include "capi_test_scene.h"

namespace bakegi::test {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Status and message of one call: the message must be non-empty and contain `expected`.
#define EXPECT_ERROR(call, status, expected)                                      \
  do {                                                                            \
    EXPECT_EQ((call), (status)) << bakegi_last_error();                           \
    EXPECT_NE(std::string(bakegi_last_error()).find(expected), std::string::npos) \
        << "message: " << bakegi_last_error();                                    \
  } while (0)

TEST(ApiErrors, VersionAndStatusNames) {
  EXPECT_EQ(bakegi_version(), uint32_t(BAKEGI_VERSION_MAJOR * 10000 + BAKEGI_VERSION_MINOR * 100 +
                                       BAKEGI_VERSION_PATCH));
  EXPECT_EQ(std::string(bakegi_version_string()).rfind("0.1.0 (embree ", 0), 0u);
  EXPECT_STREQ(bakegi_status_string(BAKEGI_ERROR_INVALID_SCENE), "BAKEGI_ERROR_INVALID_SCENE");
  EXPECT_STREQ(bakegi_status_string(BAKEGI_OK), "BAKEGI_OK");
  EXPECT_STREQ(bakegi_status_string(bakegi_status(77)), "BAKEGI_UNKNOWN_STATUS");
}

TEST(ApiErrors, NullPointersAreRefused) {
  const auto A = BAKEGI_ERROR_INVALID_ARGUMENT;
  EXPECT_ERROR(bakegi_scene_create(nullptr), A, "out_scene is NULL");
  ScenePtr scene = new_scene();
  const bakegi_material_desc material = grey_material();
  EXPECT_ERROR(bakegi_scene_add_material(nullptr, &material, nullptr), A, "scene is NULL");
  EXPECT_ERROR(bakegi_scene_add_material(scene.get(), nullptr, nullptr), A, "material is NULL");
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), nullptr, nullptr), A, "mesh is NULL");
  EXPECT_ERROR(bakegi_scene_add_light(scene.get(), nullptr, nullptr), A, "light is NULL");
  EXPECT_ERROR(bakegi_scene_add_texture(scene.get(), 1, 1, nullptr, nullptr), A,
               "rgb_pixels is NULL");
  EXPECT_ERROR(bakegi_scene_set_world(scene.get(), nullptr), A, "radiance is NULL");
  EXPECT_ERROR(bakegi_scene_validate(nullptr), A, "scene is NULL");
  EXPECT_EQ(bakegi_scene_triangle_count(nullptr), 0u);
  EXPECT_EQ(bakegi_scene_light_count(nullptr), 0u);

  const float p[3] = {0, 0, 0}, n[3] = {0, 0, 1};
  bakegi_points* points = nullptr;
  EXPECT_ERROR(bakegi_points_create(nullptr, n, nullptr, 1, &points), A, "positions is NULL");
  EXPECT_ERROR(bakegi_points_create(p, nullptr, nullptr, 1, &points), A, "normals is NULL");
  EXPECT_ERROR(bakegi_points_create(p, n, nullptr, 1, nullptr), A, "out_points is NULL");
  EXPECT_ERROR(bakegi_points_get(nullptr, nullptr, nullptr, nullptr), A, "points is NULL");
  EXPECT_EQ(bakegi_points_count(nullptr), 0u);

  EXPECT_ERROR(bakegi_file_write(nullptr, scene.get(), nullptr), A, "path is NULL");
  EXPECT_ERROR(bakegi_file_write("x.bgs", nullptr, nullptr), A, "scene is NULL");
  EXPECT_ERROR(bakegi_file_read("x.bgs", nullptr, nullptr), A, "out_scene is NULL");
  bakegi_scene* read = nullptr;
  EXPECT_ERROR(bakegi_file_read(nullptr, &read, nullptr), A, "path is NULL");
  EXPECT_EQ(read, nullptr);

  EXPECT_ERROR(bakegi_settings_create(nullptr), A, "out_settings is NULL");
  SettingsPtr settings = new_settings();
  EXPECT_ERROR(bakegi_settings_set_int(nullptr, "samples", 1), A, "settings is NULL");
  EXPECT_ERROR(bakegi_settings_set_int(settings.get(), nullptr, 1), A, "key is NULL");
  EXPECT_ERROR(bakegi_settings_set_int(settings.get(), "", 1), A, "key is empty");
  EXPECT_ERROR(bakegi_settings_set_string(settings.get(), "method", nullptr), A, "value is NULL");

  PointsPtr floor = new_floor_points(4);
  bakegi_job* job = nullptr;
  EXPECT_ERROR(bakegi_job_start(nullptr, floor.get(), nullptr, &job), A, "scene is NULL");
  EXPECT_ERROR(bakegi_job_start(scene.get(), nullptr, nullptr, &job), A, "points is NULL");
  EXPECT_ERROR(bakegi_job_start(scene.get(), floor.get(), nullptr, nullptr), A, "out_job is NULL");
  EXPECT_ERROR(bakegi_job_wait(nullptr), A, "job is NULL");
  float rgb[3];
  EXPECT_ERROR(bakegi_job_get_result(nullptr, rgb, 1), A, "job is NULL");
  size_t length = 0;
  EXPECT_ERROR(bakegi_job_get_report(nullptr, nullptr, 0, &length), A, "job is NULL");
  EXPECT_EQ(bakegi_job_progress(nullptr), 0.0);
  EXPECT_EQ(bakegi_job_is_done(nullptr), 1);
  char stage[8] = "x";
  bakegi_job_stage(nullptr, stage, sizeof stage);
  EXPECT_STREQ(stage, "");
  bakegi_job_cancel(nullptr);

  // Destroying NULL is allowed.
  bakegi_scene_destroy(nullptr);
  bakegi_points_destroy(nullptr);
  bakegi_settings_destroy(nullptr);
  bakegi_job_destroy(nullptr);
}

TEST(ApiErrors, NonFinitePositionsNameMeshAndVertex) {
  ScenePtr scene = new_scene();
  BoxMesh box;
  box.positions[3 * 5 + 1] = kNaN;
  bakegi_mesh_desc mesh = box.desc(0, 7);
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "mesh 0 (object 7), vertex 5: position is NaN");
  box.positions[3 * 5 + 1] = -kInf;
  mesh = box.desc(0, 7);
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "vertex 5: position is infinite");
  // Blender stores an infinite coordinate as FLT_MAX: finite, but refused as absurd.
  box.positions[3 * 5 + 1] = std::numeric_limits<float>::max();
  mesh = box.desc(0, 7);
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "vertex 5: position (1, 3.40282e+38, 1) is out of range");
  EXPECT_EQ(bakegi_scene_triangle_count(scene.get()), 0u);  // nothing was added
}

TEST(ApiErrors, BadMeshArrays) {
  ScenePtr scene = new_scene();
  BoxMesh box;
  box.indices[7] = 8;
  bakegi_mesh_desc mesh = box.desc(0, 3);
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "mesh 0 (object 3), triangle 2: vertex index 8 out of range (8 vertices)");

  const BoxMesh good;
  mesh = good.desc();
  mesh.positions = nullptr;
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_ARGUMENT,
               "positions is NULL");
  mesh = good.desc();
  mesh.indices = nullptr;
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_ARGUMENT,
               "indices is NULL");

  std::vector<float> normals(9 * 12, 0.0f);
  normals[9 * 4 + 3 + 2] = kInf;
  mesh = good.desc();
  mesh.corner_normals = normals.data();
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "triangle 4, corner 1: normal is infinite");
  std::vector<float> uvs(6 * 12, 0.0f);
  uvs[6 * 11 + 4] = kNaN;
  mesh = good.desc();
  mesh.corner_uvs = uvs.data();
  EXPECT_ERROR(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "triangle 11, corner 2: uv is NaN");
}

TEST(ApiErrors, MaterialAndTextureReferencesOutOfRange) {
  ScenePtr scene = new_box_scene();  // one material, one box mesh using it
  const BoxMesh box;
  bakegi_mesh_desc mesh = box.desc(5, 9);
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "mesh 1 (object 9): material index 5 out of range (1 materials)");

  scene = new_box_scene();
  std::vector<uint32_t> triangle_materials(12, 0);
  triangle_materials[3] = 2;
  mesh = box.desc();
  mesh.triangle_materials = triangle_materials.data();
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "mesh 1 (object 0), triangle 3: material index 2 out of range (1 materials)");

  scene = new_box_scene();
  bakegi_material_desc textured = grey_material();
  textured.albedo_texture = 3;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &textured, nullptr), BAKEGI_OK);
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "material 1: texture index 3 out of range (0 textures)");
}

TEST(ApiErrors, EmissionTextureReferences) {
  const auto A = BAKEGI_ERROR_INVALID_ARGUMENT;
  ScenePtr scene = new_box_scene();  // material 0, no textures
  EXPECT_ERROR(bakegi_scene_set_material_emission_texture(nullptr, 0, 0), A, "scene is NULL");
  EXPECT_ERROR(bakegi_scene_set_material_emission_texture(scene.get(), 1, BAKEGI_NO_TEXTURE), A,
               "material index 1 is not below the material count 1");
  EXPECT_ERROR(bakegi_scene_set_material_emission_texture(scene.get(), 0, 0), A,
               "material 0: emission texture index 0 is not below the texture count 0");
  EXPECT_EQ(scene->description.materials[0].emission_texture, BAKEGI_NO_TEXTURE);  // unchanged

  const float white[3] = {1.0f, 1.0f, 1.0f};
  uint32_t texture = 7;
  ASSERT_EQ(bakegi_scene_add_texture(scene.get(), 1, 1, white, &texture), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_set_material_emission_texture(scene.get(), 0, texture), BAKEGI_OK);
  EXPECT_EQ(scene->description.materials[0].emission_texture, texture);
  EXPECT_EQ(bakegi_scene_set_material_emission_texture(scene.get(), 0, BAKEGI_NO_TEXTURE),
            BAKEGI_OK);
  EXPECT_EQ(scene->description.materials[0].emission_texture, BAKEGI_NO_TEXTURE);

  // A scene file can hold any index; the scene build names it.
  scene->description.materials[0].emission_texture = 4;
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "material 0: emission texture index 4 out of range (1 textures)");
}

TEST(ApiErrors, SeeThroughMaterials) {
  const auto A = BAKEGI_ERROR_INVALID_ARGUMENT;
  const uint32_t none = BAKEGI_NO_TEXTURE;
  ScenePtr scene = new_box_scene();  // material 0, no textures
  EXPECT_ERROR(bakegi_scene_set_material_passing(nullptr, 0, 1, none, 0, 0), A, "scene is NULL");
  EXPECT_ERROR(bakegi_scene_set_material_passing(scene.get(), 1, 1, none, 0, 0), A,
               "material index 1 is not below the material count 1");
  EXPECT_ERROR(bakegi_scene_set_material_passing(scene.get(), 0, 1, 0, 0, 0), A,
               "material 0: opacity texture index 0 is not below the texture count 0");
  EXPECT_ERROR(bakegi_scene_set_material_passing(scene.get(), 0, 1.5f, none, 0, 0),
               BAKEGI_ERROR_INVALID_SCENE, "material 0: opacity must be in [0,1], got 1.5");
  EXPECT_ERROR(bakegi_scene_set_material_passing(scene.get(), 0, 1, none, NAN, 0),
               BAKEGI_ERROR_INVALID_SCENE, "material 0: transmission must be in [0,1]");
  EXPECT_ERROR(bakegi_scene_set_material_passing(scene.get(), 0, 1, none, 0.9f, 0.5f),
               BAKEGI_ERROR_INVALID_SCENE,
               "material 0: transmission IOR must be 0 (no Fresnel) or in [1, 10], got 0.5");
  EXPECT_FALSE(scene->description.materials[0].lets_light_pass());  // unchanged
  EXPECT_EQ(bakegi_scene_set_material_passing(scene.get(), 0, 1, none, 0.9f, 1.5f), BAKEGI_OK);
  EXPECT_EQ(scene->description.materials[0].transmission, 0.9f);
}

TEST(ApiErrors, BadMaterialsAndTextures) {
  ScenePtr scene = new_scene();
  bakegi_material_desc m = grey_material(1.5f);
  EXPECT_ERROR(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "material 0: albedo must be in [0,1]");
  m = grey_material();
  m.emission[1] = -1.0f;
  EXPECT_ERROR(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "material 0: emission must not be negative");
  m = grey_material();
  m.emission[2] = kNaN;
  EXPECT_ERROR(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "material 0: emission is NaN");
  m = grey_material();
  m.emission_two_sided = 2;
  EXPECT_ERROR(bakegi_scene_add_material(scene.get(), &m, nullptr), BAKEGI_ERROR_INVALID_ARGUMENT,
               "emission_two_sided must be 0 or 1");

  const std::vector<float> pixels = {0.5f, 0.5f, 0.5f, 0.2f, kNaN, 0.1f};
  EXPECT_ERROR(bakegi_scene_add_texture(scene.get(), 0, 2, pixels.data(), nullptr),
               BAKEGI_ERROR_INVALID_ARGUMENT, "size must be at least 1x1");
  EXPECT_ERROR(bakegi_scene_add_texture(scene.get(), 2, 1, pixels.data(), nullptr),
               BAKEGI_ERROR_INVALID_SCENE, "texture 0, pixel (1, 0): value is NaN");
  const std::vector<float> bright = {0.5f, 0.5f, 0.5f, 0.2f, 2.0f, 0.1f};
  EXPECT_ERROR(bakegi_scene_add_texture(scene.get(), 1, 2, bright.data(), nullptr),
               BAKEGI_ERROR_INVALID_SCENE, "texture 0, pixel (0, 1): value (0.2, 2, 0.1)");
  uint32_t index = 99;
  EXPECT_EQ(bakegi_scene_add_texture(scene.get(), 2, 1, bright.data() + 0, &index),
            BAKEGI_ERROR_INVALID_SCENE);
  EXPECT_EQ(index, 99u);  // untouched on failure
}

TEST(ApiErrors, DegenerateOnlyAndEmptyScenes) {
  ScenePtr scene = new_scene();
  const bakegi_material_desc material = grey_material();
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &material, nullptr), BAKEGI_OK);
  const bakegi_light_desc light = point_light(0, 0, 1, 1);
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &light, nullptr), BAKEGI_OK);
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "the scene is empty: it has no triangles");

  // Two triangles: one with a repeated vertex, one with three collinear vertices.
  const float positions[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0};
  const uint32_t indices[] = {0, 1, 1, 0, 1, 2};
  bakegi_mesh_desc mesh{};
  mesh.positions = positions;
  mesh.vertex_count = 4;
  mesh.indices = indices;
  mesh.triangle_count = 2;
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "all 2 triangles are degenerate");

  // One good triangle makes the scene valid (the degenerate ones are dropped, with a
  // warning that test_job checks in the report).
  const uint32_t good[] = {0, 1, 3};
  mesh.indices = good;
  mesh.triangle_count = 1;
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_validate(scene.get()), BAKEGI_OK) << bakegi_last_error();
}

TEST(ApiErrors, NoLightAtAll) {
  ScenePtr scene = new_scene();
  const bakegi_material_desc material = grey_material();
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &material, nullptr), BAKEGI_OK);
  const BoxMesh box;
  const bakegi_mesh_desc mesh = box.desc();
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  const std::string no_light =
      "no light: the scene has no lights, no emissive material and a black world";
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE, no_light);
  // A black (0 W) lamp is no light either, and the message says it is the lamp.
  const bakegi_light_desc black = point_light(0.5f, 0.5f, 0.5f, 0.0f);
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &black, nullptr), BAKEGI_OK);
  EXPECT_ERROR(bakegi_scene_validate(scene.get()), BAKEGI_ERROR_INVALID_SCENE,
               "no light: the scene's 1 light has zero power or a black color");
  // The world alone lights the scene.
  const float sky[3] = {0.1f, 0.2f, 0.3f};
  EXPECT_EQ(bakegi_scene_set_world(scene.get(), sky), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_validate(scene.get()), BAKEGI_OK) << bakegi_last_error();
  // And so does an emissive material on a triangle.
  scene = new_scene();
  bakegi_material_desc glowing = grey_material();
  glowing.emission[0] = 1.0f;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &glowing, nullptr), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_validate(scene.get()), BAKEGI_OK) << bakegi_last_error();
}

// Light values up to FLT_MAX used to pass and overflow inside the solvers (antiradiance
// failed with an internal error, meshless returned zeros): anything above 1e15 is refused
// where it enters, naming the element.
TEST(ApiErrors, LightTooBrightToBake) {
  ScenePtr scene = new_scene();
  bakegi_material_desc glowing = grey_material();
  glowing.emission[1] = 3.4e38f;
  EXPECT_ERROR(bakegi_scene_add_material(scene.get(), &glowing, nullptr),
               BAKEGI_ERROR_INVALID_SCENE, "emission is");
  EXPECT_NE(std::string(bakegi_last_error()).find("above the brightest value"), std::string::npos);
  const bakegi_light_desc lamp = point_light(0.5f, 0.5f, 0.5f, 2e15f);
  EXPECT_ERROR(bakegi_scene_add_light(scene.get(), &lamp, nullptr), BAKEGI_ERROR_INVALID_SCENE,
               "above the brightest value");
  const float sky[3] = {0.0f, 0.0f, 1e30f};
  EXPECT_ERROR(bakegi_scene_set_world(scene.get(), sky), BAKEGI_ERROR_INVALID_SCENE,
               "world radiance");
  // The brightest accepted lamp still validates.
  const bakegi_light_desc bright = point_light(0.5f, 0.5f, 0.5f, 1e15f);
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &bright, nullptr), BAKEGI_OK)
      << bakegi_last_error();
}

// Stores a value outside an enum the way a C caller can (loading it as the enum type
// would be undefined in C++).
template <typename Enum>
void set_raw(Enum& field, uint32_t value) {
  static_assert(sizeof(Enum) == sizeof value);
  std::memcpy(&field, &value, sizeof value);
}

TEST(ApiErrors, BadLightParameters) {
  ScenePtr scene = new_scene();
  const auto S = BAKEGI_ERROR_INVALID_SCENE;
  auto add = [&](const bakegi_light_desc& l) {
    return bakegi_scene_add_light(scene.get(), &l, nullptr);
  };
  bakegi_light_desc l = point_light(0, 0, 0, 1);
  l.color[1] = -0.5f;
  EXPECT_ERROR(add(l), S, "light 0 (point): color must not be negative");
  l = point_light(0, 0, 0, 1);
  l.color[0] = kInf;
  EXPECT_ERROR(add(l), S, "light 0 (point): color is infinite");
  l = point_light(kNaN, 0, 0, 1);
  EXPECT_ERROR(add(l), S, "light 0 (point): position is NaN");
  l = point_light(0, 0, 0, 1);
  l.radius = -1.0f;
  EXPECT_ERROR(add(l), S, "radius must be finite and >= 0");
  l = point_light(0, 0, 0, 1);
  set_raw(l.type, 7);
  EXPECT_ERROR(add(l), BAKEGI_ERROR_INVALID_ARGUMENT, "light 0: unknown type 7");

  bakegi_light_desc spot = point_light(0, 0, 1, 1);
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.direction[2] = -1.0f;
  spot.spot_size = 1.0f;
  spot.spot_blend = 0.2f;
  EXPECT_EQ(add(spot), BAKEGI_OK) << bakegi_last_error();
  l = spot;
  l.spot_size = 0.0f;
  EXPECT_ERROR(add(l), S, "light 1 (spot): spot_size must be in (0, pi], got 0");
  l.spot_size = 3.2f;
  EXPECT_ERROR(add(l), S, "spot_size must be in (0, pi], got 3.2");
  l = spot;
  l.spot_blend = 1.5f;
  EXPECT_ERROR(add(l), S, "spot_blend must be in [0, 1], got 1.5");
  l = spot;
  l.direction[2] = 0.0f;
  EXPECT_ERROR(add(l), S, "light 1 (spot): direction is the zero vector");

  bakegi_light_desc sun{};
  sun.type = BAKEGI_LIGHT_SUN;
  sun.direction[2] = -1.0f;
  sun.color[0] = sun.color[1] = sun.color[2] = 3.0f;
  sun.angle = std::numbers::pi_v<float>;
  EXPECT_ERROR(add(sun), S, "light 1 (sun): angle must be in [0, pi)");
  sun.angle = kNaN;
  EXPECT_ERROR(add(sun), S, "angle must be in [0, pi), got nan");

  bakegi_light_desc area{};
  area.type = BAKEGI_LIGHT_AREA;
  area.direction[2] = -1.0f;
  area.axis_u[0] = 1.0f;
  area.color[0] = area.color[1] = area.color[2] = 1.0f;
  area.shape = BAKEGI_AREA_RECTANGLE;
  area.size_x = 1.0f;
  area.size_y = 0.0f;
  EXPECT_ERROR(add(area), S, "light 1 (area): size_y must be finite and > 0, got 0");
  area.shape = BAKEGI_AREA_SQUARE;  // size_y is ignored for squares
  EXPECT_EQ(add(area), BAKEGI_OK) << bakegi_last_error();
  area.size_x = -2.0f;
  EXPECT_ERROR(add(area), S, "light 2 (area): size_x must be finite and > 0, got -2");
  area.size_x = 1.0f;
  set_raw(area.shape, 9);
  EXPECT_ERROR(add(area), BAKEGI_ERROR_INVALID_ARGUMENT, "unknown shape 9");
  area.shape = BAKEGI_AREA_SQUARE;
  area.flags = 12u;
  EXPECT_ERROR(add(area), S, "unknown flags 12");
  area.flags = 0u;
  area.spot_size = 4.0f;  // an area light's spread: at most pi
  EXPECT_ERROR(add(area), S, "light 2 (area): its spread (spot_size) must be in [0, pi], got 4");
  area.spot_size = 0.0f;
  area.shape = BAKEGI_AREA_DISK;
  area.axis_u[0] = 0.0f;
  area.axis_u[2] = 2.0f;
  EXPECT_ERROR(add(area), S, "axis_u (0, 0, 2) is parallel to direction (0, 0, -1)");
  EXPECT_EQ(bakegi_scene_light_count(scene.get()), 2u);

  float world[3] = {0.1f, -0.1f, 0.0f};
  EXPECT_ERROR(bakegi_scene_set_world(scene.get(), world), S,
               "world radiance must not be negative");
  world[1] = kNaN;
  EXPECT_ERROR(bakegi_scene_set_world(scene.get(), world), S, "world radiance is NaN");
}

TEST(ApiErrors, BadBakePoints) {
  const float positions[] = {0, 0, 0, 1, kNaN, 0};
  const float normals[] = {0, 0, 1, 0, 0, 1};
  bakegi_points* points = nullptr;
  EXPECT_ERROR(bakegi_points_create(positions, normals, nullptr, 2, &points),
               BAKEGI_ERROR_INVALID_ARGUMENT, "bake point 1: position is NaN");
  EXPECT_EQ(points, nullptr);
  const float zero_normal[] = {0, 0, 1, 0, 0, 0};
  EXPECT_ERROR(bakegi_points_create(positions, zero_normal, nullptr, 1 + 1, &points),
               BAKEGI_ERROR_INVALID_ARGUMENT, "bake point 1");
  const float good_positions[] = {0, 0, 0, 1, 1, 0};
  EXPECT_ERROR(bakegi_points_create(good_positions, zero_normal, nullptr, 2, &points),
               BAKEGI_ERROR_INVALID_ARGUMENT, "bake point 1: normal is the zero vector");
  EXPECT_ERROR(bakegi_points_create(good_positions, normals, nullptr, 0, &points),
               BAKEGI_ERROR_INVALID_ARGUMENT, "count is 0");
  // Finite but absurd: Embree aborts the process on a ray from 1e20 (ray.valid()), so such a
  // point must never reach a solver. The limit is the vertices' (+-1e12 m).
  const float far_positions[] = {0, 0, 0, 1e20f, 0, 0};
  EXPECT_ERROR(bakegi_points_create(far_positions, normals, nullptr, 2, &points),
               BAKEGI_ERROR_INVALID_ARGUMENT,
               "bake point 1: position (1e+20, 0, 0) is out of range: coordinates must be within "
               "+-1e12 m");

  // Normals are normalized on input; object ids default to 0.
  const float long_normals[] = {0, 0, 3, 0, 4, 0};
  ASSERT_EQ(bakegi_points_create(good_positions, long_normals, nullptr, 2, &points), BAKEGI_OK);
  PointsPtr owned(points);
  float n[6];
  uint32_t ids[2] = {7, 7};
  EXPECT_EQ(bakegi_points_get(points, nullptr, n, ids), BAKEGI_OK);
  EXPECT_EQ(n[2], 1.0f);
  EXPECT_EQ(n[4], 1.0f);
  EXPECT_EQ(ids[0], 0u);
  EXPECT_EQ(ids[1], 0u);
}

// The message without its "bakegi_<function>: " prefix.
std::string without_function(const std::string& message) {
  const size_t colon = message.find(": ");
  return colon == std::string::npos ? message : message.substr(colon + 2);
}

// Every case is also asked of bakegi_settings_check first, which must give the same answer
// without a scene (the add-on asks it before exporting).
TEST(ApiErrors, SettingsAreCheckedWhenAJobStarts) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(4);
  const auto A = BAKEGI_ERROR_INVALID_ARGUMENT;
  auto start = [&](bakegi_settings* settings) {
    const bakegi_status checked = bakegi_settings_check(settings);
    const std::string check_message = bakegi_last_error();
    bakegi_job* job = nullptr;
    const bakegi_status status = bakegi_job_start(scene.get(), points.get(), settings, &job);
    const std::string start_message = bakegi_last_error();
    bakegi_job_destroy(job);
    EXPECT_EQ(checked, status) << check_message;
    if (status != BAKEGI_OK) {
      EXPECT_EQ(without_function(check_message), without_function(start_message));
    }
    return status;
  };

  SettingsPtr good = new_settings("meshless");
  EXPECT_EQ(bakegi_settings_set_int(good.get(), "levels", 1), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_check(good.get()), BAKEGI_OK) << bakegi_last_error();
  EXPECT_ERROR(bakegi_settings_check(nullptr), A, "settings");

  // Path-tracer settings of a method that hands bakes to it are checked as its own.
  SettingsPtr bounces = new_settings("antiradiance");
  EXPECT_EQ(bakegi_settings_set_int(bounces.get(), "max_bounces", 1 << 20), BAKEGI_OK);
  EXPECT_ERROR(start(bounces.get()), A, "setting \"max_bounces\" must be in [1, 65536]");
  // What only the solver reads (a viewpoint that is not "x,y,z") is checked too.
  SettingsPtr viewpoint = new_settings("meshless");
  EXPECT_EQ(bakegi_settings_set_string(viewpoint.get(), "viewpoint", "north"), BAKEGI_OK);
  EXPECT_NE(bakegi_settings_check(viewpoint.get()), BAKEGI_OK);
  EXPECT_NE(std::string(bakegi_last_error()).find("viewpoint"), std::string::npos)
      << bakegi_last_error();

  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "sampels", 16), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "unknown setting \"sampels\"");

  // A key another method reads is refused too, naming it: it would pass silently otherwise.
  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "bins", 300), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A,
               "setting \"bins\" is not read by method \"pathtrace\" (its settings: method,");

  // A choice outside the schema's is named with the choices.
  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_string(settings.get(), "method", "antiradiance"), BAKEGI_OK);
  EXPECT_EQ(bakegi_settings_set_string(settings.get(), "oracle", "cube"), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A,
               "setting \"oracle\" must be \"sphere\" or \"projected\", not \"cube\"");

  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_string(settings.get(), "samples", "many"), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "setting \"samples\" must be an integer, got a string");

  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_float(settings.get(), "samples", 16.0), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "setting \"samples\" must be an integer, got a float");

  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 0), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "setting \"samples\" must be in [1, ");

  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "threads", -1), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "setting \"threads\" must be in [0, 1024], got -1");

  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "memory_budget_mb", 0), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "setting \"memory_budget_mb\" must be in [1, ");

  settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_string(settings.get(), "method", "radiosity"), BAKEGI_OK);
  EXPECT_ERROR(start(settings.get()), A, "radiosity");

  EXPECT_ERROR(bakegi_settings_set_float(settings.get(), "samples", std::nan("")), A,
               "setting \"samples\": value is NaN");
}

TEST(ApiErrors, PositionValuedSettingsAreRangeChecked) {
  // Like bake points, a viewpoint far beyond the scene would start rays Embree aborts on.
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(4);
  SettingsPtr settings = new_settings();
  ASSERT_EQ(bakegi_settings_set_string(settings.get(), "method", "meshless"), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_string(settings.get(), "viewpoint", "1e30,0,0"), BAKEGI_OK);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
  JobPtr owned(job);
  EXPECT_ERROR(bakegi_job_wait(job), BAKEGI_ERROR_INVALID_ARGUMENT,
               "setting 'viewpoint': position (1e+30, 0, 0) is out of range");
}

TEST(ApiErrors, InvalidSceneFailsTheJobWithItsMessage) {
  ScenePtr scene = new_scene();  // no triangles, no light
  PointsPtr points = new_floor_points(1);
  bakegi_job* job = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), nullptr, &job), BAKEGI_OK);
  JobPtr owned(job);
  EXPECT_ERROR(bakegi_job_wait(job), BAKEGI_ERROR_INVALID_SCENE, "the scene is empty");
  float rgb[3];
  EXPECT_ERROR(bakegi_job_get_result(job, rgb, 1), BAKEGI_ERROR_INVALID_SCENE,
               "the job failed, there is no result");
}

TEST(ApiErrors, ResultAndReportBeforeDoneAndWrongCount) {
  // Far more work than the test waits for: the job is cancelled below.
  bakegi_job* job = start_endless_job(64);
  ASSERT_NE(job, nullptr);
  JobPtr owned(job);
  std::vector<float> rgb(3 * 64);
  EXPECT_ERROR(bakegi_job_get_result(job, rgb.data(), 64), BAKEGI_ERROR_NOT_READY,
               "has not finished");
  size_t length = 0;
  EXPECT_ERROR(bakegi_job_get_report(job, nullptr, 0, &length), BAKEGI_ERROR_NOT_READY,
               "has not finished");
  bakegi_job_cancel(job);
  EXPECT_EQ(bakegi_job_wait(job), BAKEGI_ERROR_CANCELLED);

  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(64);
  SettingsPtr settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", 1), BAKEGI_OK);
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job), BAKEGI_OK);
  owned.reset(job);
  ASSERT_EQ(bakegi_job_wait(job), BAKEGI_OK) << bakegi_last_error();
  EXPECT_ERROR(bakegi_job_get_result(job, rgb.data(), 63), BAKEGI_ERROR_INVALID_ARGUMENT,
               "count 63 does not match the 64 bake points");
  EXPECT_ERROR(bakegi_job_get_result(job, nullptr, 64), BAKEGI_ERROR_INVALID_ARGUMENT,
               "out_rgb is NULL");
  EXPECT_EQ(bakegi_job_get_result(job, rgb.data(), 64), BAKEGI_OK);

  // Report: the length query, then a buffer too small (truncated, NUL-terminated), then
  // the whole text.
  EXPECT_EQ(bakegi_job_get_report(job, nullptr, 0, &length), BAKEGI_OK);
  EXPECT_GT(length, 10u);
  EXPECT_ERROR(bakegi_job_get_report(job, nullptr, 5, &length), BAKEGI_ERROR_INVALID_ARGUMENT,
               "buffer is NULL");
  EXPECT_ERROR(bakegi_job_get_report(job, nullptr, 0, nullptr), BAKEGI_ERROR_INVALID_ARGUMENT,
               "out_length is NULL");
  char small[5];
  size_t again = 0;
  EXPECT_EQ(bakegi_job_get_report(job, small, sizeof small, &again), BAKEGI_OK);
  EXPECT_EQ(again, length);
  EXPECT_EQ(std::string(small), "{\"ba");  // capacity 5: four characters and the NUL
  std::string full(length + 1, '\0');
  EXPECT_EQ(bakegi_job_get_report(job, full.data(), full.size(), nullptr), BAKEGI_OK);
  EXPECT_EQ(full[length], '\0');
  EXPECT_EQ(full[length - 1], '}');
}

TEST(ApiErrors, LastErrorIsPerThread) {
  EXPECT_EQ(bakegi_scene_create(nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  const std::string mine = bakegi_last_error();
  std::string theirs;
  std::thread other([&] {
    theirs = bakegi_last_error();  // nothing failed on that thread yet
    bakegi_scene_validate(nullptr);
  });
  other.join();
  EXPECT_EQ(theirs, "");
  EXPECT_EQ(bakegi_last_error(), mine);
}

}  // namespace
}  // namespace bakegi::test
