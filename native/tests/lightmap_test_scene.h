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

// Adds a mesh (positions: 3 floats per vertex; indices: 3 per triangle) without normals,
// UVs or materials; returns its index.
inline uint32_t add_mesh(bakegi_scene* scene, const std::vector<float>& positions,
                         const std::vector<uint32_t>& indices, uint32_t object_id) {
  bakegi_mesh_desc d{};
  d.positions = positions.data();
  d.vertex_count = uint32_t(positions.size() / 3);
  d.indices = indices.data();
  d.triangle_count = uint32_t(indices.size() / 3);
  d.object_id = object_id;
  uint32_t mesh = 0;
  EXPECT_EQ(bakegi_scene_add_mesh(scene, &d, &mesh), BAKEGI_OK) << bakegi_last_error();
  return mesh;
}

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
    return add_mesh(scene, positions, indices, object_id);
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

// Two unit quads side by side, x in [0, 1] and [1, 2], y in [0, 1] at height z, normal +z,
// sharing the edge from vertex 1 (1, 0) to vertex 4 (1, 1). Vertices 0..5: (0,0) (1,0) (2,0)
// (0,1) (1,1) (2,1); triangles: left (0,1,4) (0,4,3), right (1,2,5) (1,5,4).
struct Strip {
  std::vector<float> positions;
  std::vector<uint32_t> indices = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
  explicit Strip(float z = 0) {
    for (float y : {0.0f, 1.0f}) {
      for (float x : {0.0f, 1.0f, 2.0f}) positions.insert(positions.end(), {x, y, z});
    }
  }
  uint32_t add_to(bakegi_scene* scene, uint32_t object_id) const {
    return add_mesh(scene, positions, indices, object_id);
  }
  // Lightmap UVs per corner: each quad is a chart, uv = origin + scale * (x - x0, y) with
  // x0 = 0 on the left quad and 1 on the right one. One chart when the right quad's origin
  // is the left one's + (left_scale, 0) and the scales are equal; else the shared edge is
  // a UV seam.
  std::vector<float> uvs(glm::vec2 left_origin, float left_scale, glm::vec2 right_origin,
                         float right_scale) const {
    std::vector<float> out;
    for (size_t corner = 0; corner < indices.size(); ++corner) {
      const uint32_t v = indices[corner];
      const bool right = corner >= 6;
      const glm::vec2 local(positions[3 * v] - (right ? 1.0f : 0.0f), positions[3 * v + 1]);
      const glm::vec2 uv =
          right ? right_origin + right_scale * local : left_origin + left_scale * local;
      out.insert(out.end(), {uv.x, uv.y});
    }
    return out;
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
