// The .bgs scene file: an exact round trip of everything the C API received, and refusal
// of truncated, corrupted or forged files before anything is allocated for them.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "api/handles.h"
#include "capi_test_scene.h"
#include "scene/scene_file.h"
#include "util/bit_cast.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("bakegi_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// A scene that uses every field: a texture, two materials (one textured, one emissive with
// the same texture on its emission),
// a mesh with every optional array, a mesh with none, one light of each type and a world.
ScenePtr new_full_scene() {
  ScenePtr scene = new_scene();
  const std::vector<float> pixels = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f,
                                     0.7f, 0.8f, 0.9f, 1.0f, 0.0f, 0.25f};
  EXPECT_EQ(bakegi_scene_add_texture(scene.get(), 2, 2, pixels.data(), nullptr), BAKEGI_OK);
  bakegi_material_desc textured = grey_material(0.75f);
  textured.albedo_texture = 0;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &textured, nullptr), BAKEGI_OK);
  bakegi_material_desc glowing = grey_material(0.3f);
  glowing.emission[0] = 2.5f, glowing.emission[1] = 1.0f / 3.0f, glowing.emission[2] = 0.0f;
  glowing.emission_two_sided = 0;
  glowing.glossy[0] = 0.5f, glowing.glossy[1] = 0.25f, glowing.glossy[2] = 0.7f;
  glowing.glossy_exponent = 1234.5f;
  uint32_t glowing_id = 0;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &glowing, &glowing_id), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_set_material_emission_texture(scene.get(), glowing_id, 0), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_set_material_passing(scene.get(), glowing_id, 0.625f, 0, 0.3f, 1.5f),
            BAKEGI_OK);

  const BoxMesh box;
  std::vector<float> normals(9 * 12), uvs(6 * 12);
  for (size_t i = 0; i < normals.size(); ++i) normals[i] = std::sin(float(i)) * 0.7f;
  for (size_t i = 0; i < uvs.size(); ++i) uvs[i] = float(i) / 7.0f - 3.0f;
  std::vector<uint32_t> triangle_materials = {0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0, 1};
  bakegi_mesh_desc full = box.desc(1, 42);
  full.corner_normals = normals.data();
  full.corner_uvs = uvs.data();
  full.triangle_materials = triangle_materials.data();
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &full, nullptr), BAKEGI_OK);
  const bakegi_mesh_desc plain = box.desc(0, 43);
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &plain, nullptr), BAKEGI_OK);

  bakegi_light_desc point = point_light(0.5f, 0.25f, 0.125f, 1.1f);
  point.radius = 0.01f;
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &point, nullptr), BAKEGI_OK);
  bakegi_light_desc spot = point_light(0.1f, 0.2f, 0.9f, 7.0f);
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.direction[0] = 0.3f, spot.direction[2] = -1.0f;
  spot.spot_size = 0.8f, spot.spot_blend = 0.15f;
  spot.flags = BAKEGI_LIGHT_SPOT_WITHOUT_COSINE;
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &spot, nullptr), BAKEGI_OK);
  bakegi_light_desc sun{};
  sun.type = BAKEGI_LIGHT_SUN;
  sun.direction[1] = 0.5f, sun.direction[2] = -1.0f;
  sun.color[0] = 3.0f, sun.color[1] = 2.9f, sun.color[2] = 2.5f;
  sun.angle = 0.00918f;
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &sun, nullptr), BAKEGI_OK);
  bakegi_light_desc area{};
  area.type = BAKEGI_LIGHT_AREA;
  area.position[0] = 0.5f, area.position[1] = 0.5f, area.position[2] = 0.99f;
  area.direction[2] = -1.0f;
  area.axis_u[0] = 1.0f, area.axis_u[2] = 0.1f;
  area.color[0] = area.color[1] = area.color[2] = 4.0f;
  area.shape = BAKEGI_AREA_ELLIPSE;
  area.size_x = 0.3f, area.size_y = 0.2f;
  EXPECT_EQ(bakegi_scene_add_light(scene.get(), &area, nullptr), BAKEGI_OK);
  const float world[3] = {0.05f, 0.06f, 0.07f};
  EXPECT_EQ(bakegi_scene_set_world(scene.get(), world), BAKEGI_OK);
  // A quarter turn about z, column-major.
  const float scale[3] = {7.0f, 8.0f, 9.5f}, rotation[9] = {0, 1, 0, -1, 0, 0, 0, 0, 1};
  EXPECT_EQ(bakegi_scene_set_world_texture(scene.get(), 0, scale, rotation), BAKEGI_OK);
  bakegi_light_desc portal = area;
  portal.shape = BAKEGI_AREA_RECTANGLE;
  portal.position[0] = 1.0f;
  portal.direction[0] = -1.0f, portal.direction[2] = 0.0f;
  portal.axis_u[0] = 0.0f, portal.axis_u[1] = 1.0f, portal.axis_u[2] = 0.0f;
  EXPECT_EQ(bakegi_scene_add_portal(scene.get(), &portal), BAKEGI_OK);
  return scene;
}

PointsPtr new_points_with_ids() {
  const float positions[] = {0.1f, 0.2f, 0.0f, 0.9f, 0.8f, 0.0f, 0.5f, 0.0f, 0.5f};
  const float normals[] = {0, 0, 1, 0.6f, 0, 0.8f, 0, 1, 0};
  const uint32_t ids[] = {42, 43, 4000000000u};
  bakegi_points* points = nullptr;
  EXPECT_EQ(bakegi_points_create(positions, normals, ids, 3, &points), BAKEGI_OK);
  return PointsPtr(points);
}

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

bool same_bits(float a, float b) {
  return bakegi::bit_cast<uint32_t>(a) == bakegi::bit_cast<uint32_t>(b);
}

TEST(SceneFile, RoundTripIsExact) {
  ScenePtr scene = new_full_scene();
  PointsPtr points = new_points_with_ids();
  const std::string path = temp_path("roundtrip.bgs");
  ASSERT_EQ(bakegi_file_write(path.c_str(), scene.get(), points.get()), BAKEGI_OK)
      << bakegi_last_error();

  bakegi_scene* read_scene = nullptr;
  bakegi_points* read_points = nullptr;
  ASSERT_EQ(bakegi_file_read(path.c_str(), &read_scene, &read_points), BAKEGI_OK)
      << bakegi_last_error();
  ScenePtr scene_back(read_scene);
  PointsPtr points_back(read_points);
  ASSERT_NE(read_points, nullptr);

  const SceneDescription& a = scene->description;
  const SceneDescription& b = scene_back->description;
  ASSERT_EQ(a.textures.size(), b.textures.size());
  EXPECT_EQ(a.textures[0].width, b.textures[0].width);
  EXPECT_EQ(a.textures[0].texels(), b.textures[0].texels());
  ASSERT_EQ(a.materials.size(), 2u);
  ASSERT_EQ(b.materials.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(a.materials[i].albedo, b.materials[i].albedo);
    EXPECT_EQ(a.materials[i].albedo_texture, b.materials[i].albedo_texture);
    EXPECT_EQ(a.materials[i].emission, b.materials[i].emission);
    EXPECT_EQ(a.materials[i].emission_two_sided, b.materials[i].emission_two_sided);
    EXPECT_EQ(a.materials[i].emission_texture, b.materials[i].emission_texture);
    EXPECT_EQ(a.materials[i].glossy, b.materials[i].glossy);
    EXPECT_TRUE(same_bits(a.materials[i].glossy_exponent, b.materials[i].glossy_exponent));
    EXPECT_TRUE(same_bits(a.materials[i].opacity, b.materials[i].opacity));
    EXPECT_EQ(a.materials[i].opacity_texture, b.materials[i].opacity_texture);
    EXPECT_TRUE(same_bits(a.materials[i].transmission, b.materials[i].transmission));
    EXPECT_TRUE(same_bits(a.materials[i].transmission_ior, b.materials[i].transmission_ior));
  }
  EXPECT_FALSE(b.materials[0].lets_light_pass());
  EXPECT_EQ(b.materials[1].opacity, 0.625f);
  EXPECT_EQ(b.materials[1].opacity_texture, 0u);
  EXPECT_EQ(b.materials[1].transmission, 0.3f);
  EXPECT_EQ(b.materials[1].transmission_ior, 1.5f);
  EXPECT_TRUE(b.materials[1].has_glossy());
  EXPECT_FALSE(b.materials[1].emission_two_sided);
  EXPECT_EQ(b.materials[0].emission_texture, BAKEGI_NO_TEXTURE);
  EXPECT_EQ(b.materials[1].emission_texture, 0u);
  ASSERT_EQ(b.meshes.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(a.meshes[i].positions, b.meshes[i].positions);
    EXPECT_EQ(a.meshes[i].indices, b.meshes[i].indices);
    EXPECT_EQ(a.meshes[i].corner_normals, b.meshes[i].corner_normals);
    EXPECT_EQ(a.meshes[i].corner_uvs, b.meshes[i].corner_uvs);
    EXPECT_EQ(a.meshes[i].triangle_materials, b.meshes[i].triangle_materials);
    EXPECT_EQ(a.meshes[i].material, b.meshes[i].material);
    EXPECT_EQ(a.meshes[i].object_id, b.meshes[i].object_id);
  }
  EXPECT_EQ(b.meshes[0].corner_uvs.size(), 36u);    // optional arrays kept
  EXPECT_TRUE(b.meshes[1].corner_normals.empty());  // and absent ones stay absent
  ASSERT_EQ(b.lights.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const Light &x = a.lights[i], &y = b.lights[i];
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.direction, y.direction);  // as received, not normalized
    EXPECT_EQ(x.axis_u, y.axis_u);
    EXPECT_EQ(x.color, y.color);
    EXPECT_TRUE(same_bits(x.radius, y.radius) && same_bits(x.spot_size, y.spot_size) &&
                same_bits(x.spot_blend, y.spot_blend) && same_bits(x.angle, y.angle) &&
                same_bits(x.size_x, y.size_x) && same_bits(x.size_y, y.size_y));
    EXPECT_EQ(x.shape, y.shape);
    EXPECT_EQ(x.flags, y.flags);
  }
  EXPECT_EQ(a.world_radiance, b.world_radiance);
  EXPECT_EQ(b.world_texture.texture, 0u);
  EXPECT_EQ(a.world_texture, b.world_texture);
  EXPECT_EQ(b.world_texture.rotation[0], glm::vec3(0, 1, 0));
  ASSERT_EQ(b.portals.size(), 1u);
  EXPECT_EQ(b.portals[0].type, BAKEGI_LIGHT_AREA);
  EXPECT_EQ(b.portals[0].shape, BAKEGI_AREA_RECTANGLE);
  EXPECT_EQ(b.portals[0].position, a.portals[0].position);
  EXPECT_EQ(b.portals[0].direction, a.portals[0].direction);
  EXPECT_EQ(b.portals[0].axis_u, a.portals[0].axis_u);
  EXPECT_TRUE(same_bits(b.portals[0].size_x, a.portals[0].size_x) &&
              same_bits(b.portals[0].size_y, a.portals[0].size_y));
  EXPECT_EQ(b.portals[0].color, glm::vec3(0.0f));  // a portal emits nothing
  EXPECT_EQ(points->points.positions, points_back->points.positions);
  EXPECT_EQ(points->points.normals, points_back->points.normals);
  EXPECT_EQ(points->points.object_ids, points_back->points.object_ids);

  // Writing what was read gives the same bytes.
  const std::string again = temp_path("roundtrip2.bgs");
  ASSERT_EQ(bakegi_file_write(again.c_str(), read_scene, read_points), BAKEGI_OK);
  EXPECT_EQ(read_bytes(path), read_bytes(again));
  std::remove(path.c_str());
  std::remove(again.c_str());
}

TEST(SceneFile, PointsAreOptional) {
  ScenePtr scene = new_box_scene();
  const std::string path = temp_path("nopoints.bgs");
  ASSERT_EQ(bakegi_file_write(path.c_str(), scene.get(), nullptr), BAKEGI_OK);
  bakegi_scene* read_scene = nullptr;
  bakegi_points* read_points = reinterpret_cast<bakegi_points*>(1);
  ASSERT_EQ(bakegi_file_read(path.c_str(), &read_scene, &read_points), BAKEGI_OK);
  ScenePtr owned(read_scene);
  EXPECT_EQ(read_points, nullptr);
  EXPECT_EQ(bakegi_scene_triangle_count(read_scene), 12u);
  EXPECT_EQ(bakegi_scene_validate(read_scene), BAKEGI_OK);
  // Points in the file may also be ignored by passing NULL.
  PointsPtr points = new_floor_points(3);
  ASSERT_EQ(bakegi_file_write(path.c_str(), scene.get(), points.get()), BAKEGI_OK);
  ASSERT_EQ(bakegi_file_read(path.c_str(), &read_scene, nullptr), BAKEGI_OK);
  owned.reset(read_scene);
  std::remove(path.c_str());
}

TEST(SceneFile, EveryTruncationIsRejected) {
  ScenePtr scene = new_full_scene();
  PointsPtr points = new_points_with_ids();
  const std::vector<uint8_t> bytes = encode_scene_file(scene->description, &points->points);
  for (size_t length = 0; length < bytes.size(); ++length) {
    try {
      decode_scene_file(std::span(bytes).first(length), "cut");
      ADD_FAILURE() << "a file cut to " << length << " of " << bytes.size()
                    << " bytes was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE) << length;
    }
  }
  // And through the C API, from a real file.
  const std::string path = temp_path("truncated.bgs");
  write_bytes(path, std::vector<uint8_t>(bytes.begin(), bytes.end() - 9));
  bakegi_scene* read_scene = nullptr;
  EXPECT_EQ(bakegi_file_read(path.c_str(), &read_scene, nullptr), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(std::string(bakegi_last_error()).find("truncated"), std::string::npos)
      << bakegi_last_error();
  EXPECT_EQ(read_scene, nullptr);
  std::remove(path.c_str());
}

TEST(SceneFile, EveryBitFlipIsRejected) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(2);
  const std::vector<uint8_t> bytes = encode_scene_file(scene->description, &points->points);
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> flipped = bytes;
      flipped[i] ^= uint8_t(1u << bit);
      try {
        decode_scene_file(flipped, "flipped");
        ADD_FAILURE() << "bit " << bit << " of byte " << i << " flipped was accepted";
      } catch (const Error& e) {
        EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
      }
    }
  }
}

// FNV-1a 64, as the format specifies: lets the test forge a file with a valid checksum.
uint64_t fnv1a64(const uint8_t* data, size_t size) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (size_t i = 0; i < size; ++i) hash = (hash ^ data[i]) * 0x100000001b3ull;
  return hash;
}

void reseal(std::vector<uint8_t>& bytes) {
  const uint64_t hash = fnv1a64(bytes.data(), bytes.size() - 8);
  for (int i = 0; i < 8; ++i) bytes[bytes.size() - 8 + i] = uint8_t(hash >> (8 * i));
}

TEST(SceneFile, ForgedHugeCountsAreRejectedBeforeAllocating) {
  ScenePtr scene = new_box_scene();
  const std::vector<uint8_t> bytes = encode_scene_file(scene->description, nullptr);
  // Header 24, TEXR section (16 + 4), MATL section (16 + 4 + 68), then MESH: 16-byte
  // section header, u32 mesh count, then object_id, material, vertex count.
  const size_t vertex_count_at = 24 + 20 + 88 + 16 + 4 + 8;
  ASSERT_EQ(bytes[vertex_count_at], 8u);  // the box has 8 vertices
  std::vector<uint8_t> forged = bytes;
  for (int i = 0; i < 4; ++i) forged[vertex_count_at + i] = 0xFF;  // 4 billion vertices
  reseal(forged);
  try {
    decode_scene_file(forged, "forged");
    ADD_FAILURE() << "a forged vertex count was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
    EXPECT_NE(std::string(e.what()).find("mesh positions needs 4294967295 x 12 bytes"),
              std::string::npos)
        << e.what();
  }
  // A forged NaN with a valid checksum is refused as an invalid scene in a bad file.
  forged = bytes;
  const size_t first_position_at = vertex_count_at + 12;
  const uint32_t nan_bits = 0x7fc00000u;
  for (int i = 0; i < 4; ++i) forged[first_position_at + i] = uint8_t(nan_bits >> (8 * i));
  reseal(forged);
  try {
    decode_scene_file(forged, "forged");
    ADD_FAILURE() << "a forged NaN was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
    EXPECT_NE(std::string(e.what()).find("vertex 0: position is NaN"), std::string::npos)
        << e.what();
  }
}

// The current encoding as version 7 wrote it: material records end before the opacity and
// transmission (52 bytes instead of 68), resealed.
std::vector<uint8_t> without_passing_fields(const std::vector<uint8_t>& newest) {
  auto get_u64 = [&](size_t at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= uint64_t(newest[at + i]) << (8 * i);
    return value;
  };
  EXPECT_EQ(newest[8], 8u);
  const size_t materials_at = 24 + 16 + size_t(get_u64(24 + 8));  // after the textures
  uint32_t count = 0;
  for (int i = 0; i < 4; ++i) count |= uint32_t(newest[materials_at + 16 + i]) << (8 * i);
  EXPECT_EQ(get_u64(materials_at + 8), 4u + 68u * count);
  const size_t first = materials_at + 16 + 4;
  std::vector<uint8_t> old(newest.begin(), newest.begin() + std::ptrdiff_t(first));
  for (size_t m = 0; m < count; ++m) {
    const auto record = newest.begin() + std::ptrdiff_t(first + 68 * m);
    old.insert(old.end(), record, record + 52);
  }
  old.insert(old.end(), newest.begin() + std::ptrdiff_t(first + 68 * count), newest.end());
  auto put_u64 = [&](size_t where, uint64_t value) {
    for (int i = 0; i < 8; ++i) old[where + i] = uint8_t(value >> (8 * i));
  };
  old[8] = 7;
  put_u64(materials_at + 8, 4 + 52 * count);
  put_u64(16, old.size() - 24 - 8);
  reseal(old);
  return old;
}

// The current encoding (no portals) as a file of `version` (below 6) holds it: the world
// section without the world image and the portal count (its radiance alone, 12 bytes instead
// of 68), and materials without the version 8 fields, resealed.
std::vector<uint8_t> with_old_world(const std::vector<uint8_t>& newest, uint32_t version) {
  const std::vector<uint8_t> current = without_passing_fields(newest);
  auto get_u64 = [&](size_t at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= uint64_t(current[at + i]) << (8 * i);
    return value;
  };
  size_t at = 24;  // textures, materials, meshes, lights, then the world
  for (int section = 0; section < 4; ++section) at += 16 + size_t(get_u64(at + 8));
  EXPECT_EQ(get_u64(at + 8), 68u) << "the world section of version 7 without portals";
  std::vector<uint8_t> old(current.begin(), current.begin() + std::ptrdiff_t(at + 16 + 12));
  old.insert(old.end(), current.begin() + std::ptrdiff_t(at + 16 + 68), current.end());
  auto put_u64 = [&](size_t where, uint64_t value) {
    for (int i = 0; i < 8; ++i) old[where + i] = uint8_t(value >> (8 * i));
  };
  old[8] = uint8_t(version);
  put_u64(at + 8, 12);
  put_u64(16, old.size() - 24 - 8);
  reseal(old);
  return old;
}

// Rewrites the encoding of version 7 of a scene with one material as an older build
// wrote it: version 2 materials end before the emission texture (48 bytes instead of 52),
// version 1 ones before the glossy lobe too (32 bytes).
std::vector<uint8_t> as_version(const std::vector<uint8_t>& newest, uint32_t version) {
  const std::vector<uint8_t> current = with_old_world(newest, version);
  auto get_u64 = [&](size_t at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= uint64_t(current[at + i]) << (8 * i);
    return value;
  };
  const size_t textures_at = 24;  // after the file header
  const size_t materials_at = textures_at + 16 + size_t(get_u64(textures_at + 8));
  EXPECT_EQ(get_u64(materials_at + 8), 4u + 52u) << "one material of 52 bytes";
  const size_t material_at = materials_at + 16 + 4;
  const size_t kept = version == 1 ? 32 : 48;
  std::vector<uint8_t> old(current.begin(), current.begin() + std::ptrdiff_t(material_at + kept));
  old.insert(old.end(), current.begin() + std::ptrdiff_t(material_at + 52), current.end());
  auto put_u64 = [&](size_t at, uint64_t value) {
    for (int i = 0; i < 8; ++i) old[at + i] = uint8_t(value >> (8 * i));
  };
  old[8] = uint8_t(version);            // format version
  put_u64(materials_at + 8, 4 + kept);  // MATL section bytes
  put_u64(16, old.size() - 24 - 8);     // payload bytes
  reseal(old);
  return old;
}

// One emissive, half see-through material with a glossy lobe and an emission texture, on the
// box.
ScenePtr new_textured_emitter_scene() {
  ScenePtr scene = new_scene();
  const float texel[3] = {0.25f, 0.5f, 1.0f};
  EXPECT_EQ(bakegi_scene_add_texture(scene.get(), 1, 1, texel, nullptr), BAKEGI_OK);
  bakegi_material_desc material = grey_material(0.25f);
  material.emission[0] = material.emission[1] = material.emission[2] = 3.0f;
  material.glossy[0] = material.glossy[1] = material.glossy[2] = 0.5f;
  material.glossy_exponent = 20.0f;
  EXPECT_EQ(bakegi_scene_add_material(scene.get(), &material, nullptr), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_set_material_emission_texture(scene.get(), 0, 0), BAKEGI_OK);
  EXPECT_EQ(bakegi_scene_set_material_passing(scene.get(), 0, 0.5f, BAKEGI_NO_TEXTURE, 0.0f, 0.0f),
            BAKEGI_OK);
  const BoxMesh box;
  const bakegi_mesh_desc mesh = box.desc();
  EXPECT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  return scene;
}

TEST(SceneFile, OlderVersionsAreStillRead) {
  ScenePtr scene = new_textured_emitter_scene();
  const std::vector<uint8_t> v3 = encode_scene_file(scene->description, nullptr);
  EXPECT_EQ(v3[8], kSceneFileVersion);
  const Material& written = scene->description.materials[0];

  // Version 2: glossy lobes, no emission textures.
  const SceneFile v2 = decode_scene_file(as_version(v3, 2), "v2");
  ASSERT_EQ(v2.scene.materials.size(), 1u);
  EXPECT_EQ(v2.scene.materials[0].emission, written.emission);
  EXPECT_EQ(v2.scene.materials[0].glossy, written.glossy);
  EXPECT_EQ(v2.scene.materials[0].glossy_exponent, written.glossy_exponent);
  EXPECT_EQ(v2.scene.materials[0].emission_texture, BAKEGI_NO_TEXTURE);
  EXPECT_EQ(v2.scene.textures.size(), 1u);
  EXPECT_EQ(v2.scene.meshes[0].positions, scene->description.meshes[0].positions);

  // Version 1: diffuse materials.
  const SceneFile v1 = decode_scene_file(as_version(v3, 1), "v1");
  ASSERT_EQ(v1.scene.materials.size(), 1u);
  EXPECT_EQ(v1.scene.materials[0].albedo, written.albedo);
  EXPECT_EQ(v1.scene.materials[0].emission, written.emission);
  EXPECT_FALSE(v1.scene.materials[0].has_glossy());
  EXPECT_EQ(v1.scene.materials[0].emission_texture, BAKEGI_NO_TEXTURE);
  EXPECT_EQ(v1.scene.meshes.size(), scene->description.meshes.size());
  EXPECT_EQ(v1.scene.meshes[0].positions, scene->description.meshes[0].positions);

  // The current version keeps it.
  EXPECT_EQ(decode_scene_file(v3, "v3").scene.materials[0].emission_texture, 0u);
  EXPECT_EQ(decode_scene_file(v3, "v3").scene.materials[0].opacity, 0.5f);

  // Version 7: no see-through surfaces; its materials are opaque.
  const SceneFile v7 = decode_scene_file(without_passing_fields(v3), "v7");
  EXPECT_EQ(v7.scene.materials[0].emission_texture, 0u);
  EXPECT_FALSE(v7.scene.materials[0].lets_light_pass());

  std::vector<uint8_t> future = v3;
  future[8] = uint8_t(kSceneFileVersion + 1);
  reseal(future);
  try {
    decode_scene_file(future, "future");
    ADD_FAILURE() << "a future format version was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
    const std::string expected =
        "format version " + std::to_string(kSceneFileVersion + 1) + " is not supported";
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

// A version 6 file (the world section ends after the image's rotation) reads without portals.
TEST(SceneFile, Version6HasNoPortals) {
  ScenePtr scene = new_textured_emitter_scene();
  const std::vector<uint8_t> current =
      without_passing_fields(encode_scene_file(scene->description, nullptr));
  auto get_u64 = [&](size_t at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= uint64_t(current[at + i]) << (8 * i);
    return value;
  };
  size_t at = 24;
  for (int section = 0; section < 4; ++section) at += 16 + size_t(get_u64(at + 8));
  ASSERT_EQ(get_u64(at + 8), 68u);
  std::vector<uint8_t> old(current.begin(), current.begin() + std::ptrdiff_t(at + 16 + 64));
  old.insert(old.end(), current.begin() + std::ptrdiff_t(at + 16 + 68), current.end());
  auto put_u64 = [&](size_t where, uint64_t value) {
    for (int i = 0; i < 8; ++i) old[where + i] = uint8_t(value >> (8 * i));
  };
  old[8] = 6;
  put_u64(at + 8, 64);
  put_u64(16, old.size() - 24 - 8);
  reseal(old);
  const SceneFile v6 = decode_scene_file(old, "v6");
  EXPECT_TRUE(v6.scene.portals.empty());
  EXPECT_EQ(v6.scene.world_radiance, scene->description.world_radiance);
  // The same bytes labelled version 7 lack the portal count: refused, not misread.
  old[8] = 7;
  reseal(old);
  EXPECT_THROW(decode_scene_file(old, "v7 without portal count"), Error);
}

// A version 3 file (light records of 80 bytes, no flags) reads with flags 0.
TEST(SceneFile, Version3LightsHaveNoFlags) {
  ScenePtr scene = new_scene();
  bakegi_light_desc spot = point_light(0.1f, 0.2f, 0.9f, 7.0f);
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.direction[2] = -1.0f;
  spot.spot_size = 0.8f;
  spot.flags = BAKEGI_LIGHT_SPOT_WITHOUT_COSINE;
  ASSERT_EQ(bakegi_scene_add_light(scene.get(), &spot, nullptr), BAKEGI_OK);
  ASSERT_EQ(bakegi_scene_add_light(scene.get(), &spot, nullptr), BAKEGI_OK);
  const std::vector<uint8_t> v4 = with_old_world(encode_scene_file(scene->description, nullptr), 4);
  auto get_u64 = [](const std::vector<uint8_t>& bytes, size_t at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= uint64_t(bytes[at + i]) << (8 * i);
    return value;
  };
  // Sections (id, reserved, u64 size, payload) from byte 24: textures, materials, meshes,
  // lights. The lights' payload is a u32 count and 84-byte records.
  size_t at = 24;
  for (int section = 0; section < 3; ++section) at += 16 + size_t(get_u64(v4, at + 8));
  ASSERT_EQ(get_u64(v4, at + 8), 4u + 2u * 84u);
  std::vector<uint8_t> v3(v4.begin(), v4.begin() + std::ptrdiff_t(at + 16 + 4));
  for (size_t light = 0; light < 2; ++light) {
    const size_t record = at + 16 + 4 + light * 84;
    v3.insert(v3.end(), v4.begin() + std::ptrdiff_t(record),
              v4.begin() + std::ptrdiff_t(record + 80));
  }
  v3.insert(v3.end(), v4.begin() + std::ptrdiff_t(at + 16 + 4 + 2 * 84), v4.end());
  auto put_u64 = [&](size_t where, uint64_t value) {
    for (int i = 0; i < 8; ++i) v3[where + i] = uint8_t(value >> (8 * i));
  };
  v3[8] = 3;
  put_u64(at + 8, 4 + 2 * 80);
  put_u64(16, v3.size() - 24 - 8);
  reseal(v3);
  const SceneFile read = decode_scene_file(v3, "v3");
  ASSERT_EQ(read.scene.lights.size(), 2u);
  for (const Light& l : read.scene.lights) {
    EXPECT_EQ(l.flags, 0u);
    EXPECT_EQ(l.type, BAKEGI_LIGHT_SPOT);
    EXPECT_EQ(l.spot_size, 0.8f);
  }
  EXPECT_EQ(decode_scene_file(v4, "v4").scene.lights[1].flags,
            uint32_t(BAKEGI_LIGHT_SPOT_WITHOUT_COSINE));
}

TEST(SceneFile, ShareCandidatesRoundTripAndVersion4HasNone) {
  ScenePtr scene = new_box_scene();
  PointsPtr points = new_floor_points(4);
  const std::vector<uint32_t> candidates = {0, 0, 2, 2};
  ASSERT_EQ(bakegi_points_set_share_candidates(points.get(), candidates.data(), 4), BAKEGI_OK);
  const SceneFile v5 =
      decode_scene_file(encode_scene_file(scene->description, &points->points), "v5");
  ASSERT_TRUE(v5.points);
  EXPECT_EQ(v5.points->share_candidates, candidates);

  // A version 4 file: the points section ends after the object ids (no candidate count).
  points->points.share_candidates.clear();
  const std::vector<uint8_t> current =
      with_old_world(encode_scene_file(scene->description, &points->points), 5);
  auto get_u64 = [&](size_t at) {
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) value |= uint64_t(current[at + i]) << (8 * i);
    return value;
  };
  size_t at = 24;  // textures, materials, meshes, lights, world, then the points
  for (int section = 0; section < 5; ++section) at += 16 + size_t(get_u64(at + 8));
  const uint64_t points_bytes = get_u64(at + 8);
  ASSERT_EQ(at + 16 + points_bytes + 8, current.size());
  ASSERT_EQ(get_u64(current.size() - 16), 0u) << "the candidate count ends the section";
  std::vector<uint8_t> v4(current.begin(), current.end() - 16);
  v4.resize(v4.size() + 8);  // the hash
  auto put_u64 = [&](size_t where, uint64_t value) {
    for (int i = 0; i < 8; ++i) v4[where + i] = uint8_t(value >> (8 * i));
  };
  v4[8] = 4;
  put_u64(at + 8, points_bytes - 8);
  put_u64(16, v4.size() - 24 - 8);
  reseal(v4);
  const SceneFile read = decode_scene_file(v4, "v4");
  ASSERT_TRUE(read.points);
  EXPECT_EQ(read.points->positions, points->points.positions);
  EXPECT_TRUE(read.points->share_candidates.empty());

  // Candidates that break the rules are refused when read, like any invalid content.
  points->points.share_candidates = {0, 3, 2, 2};
  EXPECT_THROW(decode_scene_file(encode_scene_file(scene->description, &points->points), "bad"),
               Error);
}

TEST(SceneFile, MissingFilesAndForeignFiles) {
  bakegi_scene* read_scene = nullptr;
  const std::string missing = temp_path("does_not_exist.bgs");
  EXPECT_EQ(bakegi_file_read(missing.c_str(), &read_scene, nullptr), BAKEGI_ERROR_IO);
  EXPECT_NE(std::string(bakegi_last_error()).find("does_not_exist.bgs"), std::string::npos);
  ScenePtr scene = new_box_scene();
  EXPECT_EQ(bakegi_file_write("/nonexistent-dir/x.bgs", scene.get(), nullptr), BAKEGI_ERROR_IO);
  EXPECT_NE(std::string(bakegi_last_error()).find("cannot write /nonexistent-dir/x.bgs"),
            std::string::npos)
      << bakegi_last_error();

  const std::string foreign = temp_path("foreign.bgs");
  write_bytes(foreign, std::vector<uint8_t>(100, 'x'));
  EXPECT_EQ(bakegi_file_read(foreign.c_str(), &read_scene, nullptr), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(std::string(bakegi_last_error()).find("not a bakegi scene file"), std::string::npos);
  EXPECT_EQ(read_scene, nullptr);
  std::remove(foreign.c_str());
}

}  // namespace
}  // namespace bakegi::test
