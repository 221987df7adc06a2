// Helpers for the lightmap C API tests: quads with lightmap UVs, a lit scene to add them to,
// an owning lightmaps handle and a fixture with a temporary folder for the files written.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "bakegi/bakegi.h"
#include "bakegi/bakegi_handles.hpp"

namespace bakegi::test {

struct LightmapsDeleter {
  void operator()(bakegi_lightmaps* l) const { bakegi_lightmaps_destroy(l); }
};
using LightmapsPtr = std::unique_ptr<bakegi_lightmaps, LightmapsDeleter>;

// A quad with its positions, indices and lightmap UVs (the UV square, diagonal 0-2).
struct Quad {
  std::vector<float> positions;
  std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
  std::vector<float> uvs = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
  // centre +- u +- v, normal u x v.
  Quad(glm::vec3 c, glm::vec3 u, glm::vec3 v) {
    for (const glm::vec3& p : {c - u - v, c + u - v, c + u + v, c - u + v}) {
      positions.insert(positions.end(), {p.x, p.y, p.z});
    }
  }
  uint32_t add_to(bakegi_scene* scene, uint32_t object_id) const {
    bakegi_mesh_desc d{};
    d.positions = positions.data();
    d.vertex_count = 4;
    d.indices = indices.data();
    d.triangle_count = 2;
    d.object_id = object_id;
    uint32_t mesh = 0;
    EXPECT_EQ(bakegi_scene_add_mesh(scene, &d, &mesh), BAKEGI_OK) << bakegi_last_error();
    return mesh;
  }
  // The UVs scaled by `scale` and moved by `offset` (placed in a region of an atlas).
  std::vector<float> placed_uvs(glm::vec2 scale, glm::vec2 offset) const {
    std::vector<float> placed = uvs;
    for (size_t i = 0; i < placed.size(); i += 2) {
      placed[i] = placed[i] * scale.x + offset.x;
      placed[i + 1] = placed[i + 1] * scale.y + offset.y;
    }
    return placed;
  }
};

inline SceneHandle lit_scene() {
  bakegi_scene* scene = nullptr;
  EXPECT_EQ(bakegi_scene_create(&scene), BAKEGI_OK);
  bakegi_material_desc m{};
  m.albedo[0] = m.albedo[1] = m.albedo[2] = 0.5f;
  m.albedo_texture = BAKEGI_NO_TEXTURE;
  EXPECT_EQ(bakegi_scene_add_material(scene, &m, nullptr), BAKEGI_OK);
  bakegi_light_desc l{};
  l.type = BAKEGI_LIGHT_POINT;
  l.position[2] = 3;
  l.color[0] = l.color[1] = l.color[2] = 1;
  EXPECT_EQ(bakegi_scene_add_light(scene, &l, nullptr), BAKEGI_OK);
  return SceneHandle(scene);
}

inline LightmapsPtr new_lightmaps() {
  bakegi_lightmaps* l = nullptr;
  EXPECT_EQ(bakegi_lightmaps_create(&l), BAKEGI_OK);
  return LightmapsPtr(l);
}

// A fixture with a fresh temporary folder per test, removed afterwards.
class LightmapFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    directory_ = std::filesystem::path(::testing::TempDir()) /
                 ("bakegi_" + std::string(test->test_suite_name()) + "_" + test->name());
    std::filesystem::remove_all(directory_);
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  std::string path(const std::string& name) const { return (directory_ / name).string(); }
  std::filesystem::path directory_;
};

}  // namespace bakegi::test
