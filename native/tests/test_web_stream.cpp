// What the web stream sends (web/): the grid's vertices corners first, coarse to fine and
// stratified over slices (§4.1); the progressive mesh (§4.2) whose faces are valid from the
// vertex count they are streamed at, resolve to the input mesh in the end and cover the
// surface at every level on the way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>
#include <vector>

#include <glm/geometric.hpp>

// stb_image (Debian's libstb-dev), compiled here, private to this file: reads the exported PNGs.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include "api/handles.h"
#include "capi_test_scene.h"
#include "grid/grid_visibility_volume.h"
#include "test_meshes.h"
#include "util/error.h"
#include "util/file_bytes.h"
#include "web/grid_stream_order.h"
#include "web/progressive_mesh.h"

namespace bakegi {
namespace {

TEST(GridStreamOrder, CornersFirstThenCoarseToFineSpreadOverSlices) {
  const GridLayout layout = make_grid_layout({0, 0, 0}, {2, 1, 1}, {17, 9, 9});
  const std::vector<uint32_t> order = grid_stream_order(layout);
  ASSERT_EQ(order.size(), layout.vertex_count());
  EXPECT_EQ(std::set<uint32_t>(order.begin(), order.end()).size(), order.size());
  std::set<size_t> corners;
  for (uint32_t c = 0; c < 8; ++c) {
    corners.insert(layout.vertex_index(c & 1 ? 16 : 0, c & 2 ? 8 : 0, c & 4 ? 8 : 0));
  }
  EXPECT_EQ(std::set<size_t>(order.begin(), order.begin() + 8), corners);
  // Coarse to fine: a vertex on the stride-2 lattice never follows one that is only on the
  // stride-1 lattice.
  auto coords = [&](uint32_t v) { return glm::uvec3(v % 17, (v / 17) % 9, v / (17 * 9)); };
  auto on_even_lattice = [&](uint32_t v) {
    const glm::uvec3 c = coords(v);
    return c.x % 2 == 0 && c.y % 2 == 0 && c.z % 2 == 0;
  };
  const auto first_odd =
      std::find_if(order.begin() + 8, order.end(), [&](uint32_t v) { return !on_even_lattice(v); });
  EXPECT_TRUE(std::all_of(first_odd, order.end(),
                          [&](uint32_t v) { return !on_even_lattice(v) || corners.count(v); }));
  // Stratified: the finest level's first 3 x 17 vertices put 3 in each x slice.
  std::vector<int> per_slice(17, 0);
  for (auto it = first_odd; it != first_odd + 3 * 17; ++it) ++per_slice[coords(*it).x];
  EXPECT_TRUE(std::all_of(per_slice.begin(), per_slice.end(), [](int n) { return n == 3; }));
  // Random within slices, but the same for the same seed.
  EXPECT_EQ(grid_stream_order(layout), order);
  EXPECT_NE(grid_stream_order(layout, 2), order);
}

using test::sphere;
using test::TestMesh;

// The area a client draws with the first n vertices (faces valid at n, corners resolved).
double drawn_area(const ProgressiveMesh& pm, const std::vector<glm::vec3>& streamed, uint32_t n,
                  size_t* faces) {
  double area = 0.0;
  *faces = 0;
  for (size_t f = 0; f < pm.valid_at.size() && pm.valid_at[f] <= n; ++f, ++*faces) {
    glm::vec3 p[3];
    for (int c = 0; c < 3; ++c) p[c] = streamed[pm.resolve(pm.faces[3 * f + c], n)];
    area += 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
  }
  return area;
}

TEST(ProgressiveMesh, FacesAreValidFromTheirCountAndEndAsTheInput) {
  const TestMesh mesh = sphere(48, 96);  // 9,024 triangles
  const ProgressiveMesh pm = build_progressive_mesh(mesh.positions, mesh.indices);
  const uint32_t total = uint32_t(pm.original_vertex.size());
  ASSERT_EQ(total, mesh.positions.size());
  ASSERT_GE(pm.level_vertices.size(), 4u);  // 9,024 -> ... -> 64 in quarters
  EXPECT_EQ(pm.level_vertices.back(), total);
  EXPECT_TRUE(std::is_sorted(pm.level_vertices.begin(), pm.level_vertices.end()));
  for (uint32_t v = 0; v < total; ++v) EXPECT_LE(pm.parent[v], v);
  EXPECT_TRUE(std::is_sorted(pm.valid_at.begin(), pm.valid_at.end()));

  // In the end the faces are the input's, in the streamed numbering.
  std::multiset<std::vector<uint32_t>> input, streamed_faces;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    input.insert({mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]});
  }
  for (size_t t = 0; t < pm.faces.size(); t += 3) {
    streamed_faces.insert({pm.original_vertex[pm.faces[t]], pm.original_vertex[pm.faces[t + 1]],
                           pm.original_vertex[pm.faces[t + 2]]});
  }
  EXPECT_EQ(streamed_faces, input);

  // A face streamed at n is valid there and was not valid one vertex earlier (the server
  // sends it as soon as it can).
  for (size_t f = 0; f < pm.valid_at.size(); f += 7) {
    const uint32_t n = pm.valid_at[f];
    uint32_t r[3], q[3];
    for (int c = 0; c < 3; ++c) {
      r[c] = pm.resolve(pm.faces[3 * f + c], n);
      q[c] = pm.resolve(pm.faces[3 * f + c], n - 1);
    }
    EXPECT_TRUE(r[0] != r[1] && r[1] != r[2] && r[0] != r[2] && r[0] != UINT32_MAX) << f;
    EXPECT_FALSE(q[0] != q[1] && q[1] != q[2] && q[0] != q[2] && q[0] != UINT32_MAX &&
                 q[1] != UINT32_MAX && q[2] != UINT32_MAX)
        << f;
  }
}

TEST(ProgressiveMesh, EveryLevelCoversTheSurface) {
  const TestMesh mesh = sphere(48, 96);
  const ProgressiveMesh pm = build_progressive_mesh(mesh.positions, mesh.indices);
  std::vector<glm::vec3> streamed;
  for (const uint32_t v : pm.original_vertex) streamed.push_back(mesh.positions[v]);
  size_t faces = 0;
  const double full = drawn_area(pm, streamed, pm.level_vertices.back(), &faces);
  EXPECT_EQ(faces, mesh.indices.size() / 3);
  EXPECT_NEAR(full, 4.0 * std::numbers::pi, 0.01 * 4.0 * std::numbers::pi);
  size_t previous_faces = 0;
  for (const uint32_t n : pm.level_vertices) {
    const double area = drawn_area(pm, streamed, n, &faces);
    // A closed sphere at every level: no holes (area within 25% of the full sphere, the
    // coarsest 64-triangle level being an inscribed polyhedron) and more faces as it refines.
    // Collapse targets taken as the nearest kept neighbour, not the simplifier's own, fold a
    // few faces over others in between (measured: 3% more area at the 596-face level).
    EXPECT_GT(area, 0.75 * full) << n << " area " << area;
    EXPECT_LT(area, 1.05 * full) << n << " area " << area;
    EXPECT_GT(faces, previous_faces) << n;
    previous_faces = faces;
  }
  EXPECT_LE(pm.level_vertices.front(), 64u);
}

TEST(ProgressiveMesh, BadIndicesAreRefused) {
  const std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(build_progressive_mesh(positions, std::vector<uint32_t>{0, 1, 3}), Error);
  EXPECT_THROW(build_progressive_mesh(positions, std::vector<uint32_t>{0, 1}), Error);
  EXPECT_TRUE(build_progressive_mesh(positions, std::vector<uint32_t>{}).faces.empty());
}

TEST(WebExport, WritesAGltfWithItsBufferAndTheGrid) {
  const test::ScenePtr scene = test::new_box_scene();
  const float bounds_min[3] = {0, 0, 0}, bounds_max[3] = {1, 1, 1};
  bakegi_grid* raw = nullptr;
  ASSERT_EQ(bakegi_grid_create(bounds_min, bounds_max, 0.25f, 0, &raw), BAKEGI_OK);
  const GridHandle grid(raw);
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "bakegi_web_export_test";
  std::filesystem::remove_all(folder);
  const float camera[9] = {0.5f, -2.0f, 0.5f, 0.7071f, 0.0f, 0.0f, 0.7071f, 0.7f, 1.5f};
  ASSERT_EQ(bakegi_web_export(scene.get(), grid.get(), folder.string().c_str(), camera), BAKEGI_OK)
      << bakegi_last_error();
  std::ifstream json_file(folder / "scene.gltf");
  const std::string json((std::istreambuf_iterator<char>(json_file)), {});
  EXPECT_EQ(json.rfind("{\"asset\":{\"version\":\"2.0\"", 0), 0u);
  const uintmax_t bin = std::filesystem::file_size(folder / "scene.bin");
  EXPECT_NE(json.find("\"byteLength\":" + std::to_string(bin) + "}]"), std::string::npos);
  EXPECT_NE(json.find("\"bakegi_progressive\""), std::string::npos);
  EXPECT_NE(json.find("\"cameras\""), std::string::npos);
  EXPECT_NE(json.find("\"grid\":\"grid.bgivg\""), std::string::npos);
  bakegi_grid* read = nullptr;
  ASSERT_EQ(bakegi_grid_read_file((folder / "grid.bgivg").string().c_str(), &read), BAKEGI_OK);
  bakegi_grid_destroy(read);
  // The page's visibility volume beside it, named in the glTF, for the grid's 4^3 vertices
  // (cut 8 x 8 x 8 each: a subvoxel is about 1/64 of the grid's side, at most 8 a cell).
  EXPECT_NE(json.find("\"grid_visibility\":\"grid_visibility.bin\""), std::string::npos);
  const std::vector<uint8_t> visibility =
      read_file_bytes(folder / "grid_visibility.bin", uint64_t(1) << 20);
  EXPECT_EQ(decode_visibility_file(visibility, grid_of(grid.get()).layout).subvoxel_count(),
            32u * 32u * 32u);
  // Read through the C API as the page reads it; the flag stands alone.
  const float position[3] = {0.5f, 0.5f, 0.0f}, normal[3] = {0, 0, 1};
  float rgb[3];
  uint8_t code = 9;
  EXPECT_EQ(bakegi_grid_evaluate_in_scene(grid.get(), scene.get(), position, normal, 1,
                                          BAKEGI_GRID_TRILINEAR, BAKEGI_GRID_SQUARED,
                                          BAKEGI_GRID_PAGE_VISIBILITY, rgb, &code),
            BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_EQ(code, 1);  // the grid was never baked: every vertex invalid, none seen
  EXPECT_EQ(bakegi_grid_evaluate_in_scene(grid.get(), scene.get(), position, normal, 1,
                                          BAKEGI_GRID_TRILINEAR, BAKEGI_GRID_SQUARED,
                                          BAKEGI_GRID_PAGE_VISIBILITY | BAKEGI_GRID_VISIBILITY, rgb,
                                          &code),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_grid_evaluate_in_scene(grid.get(), scene.get(), position, normal, 1,
                                          BAKEGI_GRID_TRICUBIC, BAKEGI_GRID_SQUARED,
                                          BAKEGI_GRID_PAGE_VISIBILITY, rgb, &code),
            BAKEGI_ERROR_INVALID_ARGUMENT);

  // The stream helpers: a permutation, and vertices encoded as the file holds them.
  std::vector<uint32_t> order(4 * 4 * 4);
  ASSERT_EQ(bakegi_grid_stream_order(grid.get(), 1, order.data()), BAKEGI_OK);
  EXPECT_EQ(std::set<uint32_t>(order.begin(), order.end()).size(), order.size());
  std::vector<uint8_t> quantized(2 * 42), factored(2 * 144);
  EXPECT_EQ(bakegi_grid_encode_vertices(grid.get(), order.data(), 2, BAKEGI_GRID_QUANTIZED,
                                        quantized.data()),
            BAKEGI_OK);
  EXPECT_EQ(bakegi_grid_encode_vertices(grid.get(), order.data(), 2, BAKEGI_GRID_FACTORED,
                                        factored.data()),
            BAKEGI_OK);
  const uint32_t outside = 64;
  EXPECT_EQ(
      bakegi_grid_encode_vertices(grid.get(), &outside, 1, BAKEGI_GRID_QUANTIZED, quantized.data()),
      BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(
      bakegi_grid_encode_vertices(grid.get(), order.data(), 1, BAKEGI_GRID_FLOAT, quantized.data()),
      BAKEGI_ERROR_INVALID_ARGUMENT);
  const float bad_camera[9] = {0, 0, 0, 0, 0, 0, 1, 0.0f, 1.0f};
  EXPECT_EQ(bakegi_web_export(scene.get(), nullptr, folder.string().c_str(), bad_camera),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  std::filesystem::remove_all(folder);
}

// What the page needs to draw the lamps as the bake does: Cast Shadow off on a lamp and on an
// area light, and a note where an area light's Spread is narrower than the page can draw.
TEST(WebExport, SaysWhichLightsCastNoShadowAndNotesANarrowSpread) {
  const test::ScenePtr scene = test::new_box_scene();  // its point light casts shadows
  bakegi_light_desc spot = test::point_light(0.5f, 0.5f, 0.9f, 1.0f);
  spot.type = BAKEGI_LIGHT_SPOT;
  spot.direction[2] = -1.0f;
  spot.spot_size = 1.0f;
  spot.flags = BAKEGI_LIGHT_NO_SHADOW;
  ASSERT_EQ(bakegi_scene_add_light(scene.get(), &spot, nullptr), BAKEGI_OK) << bakegi_last_error();
  bakegi_light_desc area{};
  area.type = BAKEGI_LIGHT_AREA;
  area.position[0] = area.position[1] = 0.5f;
  area.position[2] = 0.99f;
  area.direction[2] = -1.0f;
  area.axis_u[0] = 1.0f;
  area.color[0] = area.color[1] = area.color[2] = 1.0f;
  area.shape = BAKEGI_AREA_SQUARE;
  area.size_x = 0.2f;
  area.spot_size = std::numbers::pi_v<float>;  // Lambertian
  ASSERT_EQ(bakegi_scene_add_light(scene.get(), &area, nullptr), BAKEGI_OK) << bakegi_last_error();
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "bakegi_web_export_lights_test";
  const auto export_json = [&] {
    std::filesystem::remove_all(folder);
    EXPECT_EQ(bakegi_web_export(scene.get(), nullptr, folder.string().c_str(), nullptr), BAKEGI_OK)
        << bakegi_last_error();
    std::ifstream json_file(folder / "scene.gltf");
    return std::string((std::istreambuf_iterator<char>(json_file)), {});
  };
  std::string json = export_json();
  EXPECT_EQ(json.find("\"type\":\"point\",\"extras\""), std::string::npos);  // the point casts
  EXPECT_NE(json.find("\"extras\":{\"cast_shadow\":false},\"type\":\"spot\""), std::string::npos);
  EXPECT_NE(json.find("\"cast_shadow\":true}]"), std::string::npos);  // the area light
  EXPECT_EQ(json.find("Spread"), std::string::npos);

  area.spot_size = 1.0f;
  area.flags = BAKEGI_LIGHT_NO_SHADOW;
  ASSERT_EQ(bakegi_scene_clear_lights(scene.get()), BAKEGI_OK);
  ASSERT_EQ(bakegi_scene_add_light(scene.get(), &area, nullptr), BAKEGI_OK) << bakegi_last_error();
  json = export_json();
  EXPECT_NE(json.find("\"cast_shadow\":false}]"), std::string::npos);
  EXPECT_NE(json.find("an area light's Spread is under 180 degrees"), std::string::npos);
  std::filesystem::remove_all(folder);
}

TEST(WebExport, WritesSeeThroughMaterialsAndTheirAlphaMaps) {
  // A glass (passing 75%) and a half-present leaf card (cut out by a 2 x 1 texture: a hole and a
  // solid texel) beside the box's opaque grey: the page gets each one's opacity and transmission,
  // and the leaf's alpha map as linear grey, opacity x the texture's red channel.
  const test::ScenePtr scene = test::new_box_scene();
  const float texels[6] = {0.0f, 0.3f, 0.3f, 1.0f, 0.3f, 0.3f};
  uint32_t mask = 0, glass = 0, leaf = 0;
  ASSERT_EQ(bakegi_scene_add_texture(scene.get(), 2, 1, texels, &mask), BAKEGI_OK);
  const bakegi_material_desc black = test::grey_material(0.0f);
  ASSERT_EQ(bakegi_scene_add_material(scene.get(), &black, &glass), BAKEGI_OK);
  ASSERT_EQ(bakegi_scene_add_material(scene.get(), &black, &leaf), BAKEGI_OK);
  ASSERT_EQ(
      bakegi_scene_set_material_passing(scene.get(), glass, 1.0f, BAKEGI_NO_TEXTURE, 0.75f, 1.5f),
      BAKEGI_OK);
  ASSERT_EQ(bakegi_scene_set_material_passing(scene.get(), leaf, 0.5f, mask, 0.0f, 0.0f),
            BAKEGI_OK);
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / "bakegi_web_export_see_through_test";
  std::filesystem::remove_all(folder);
  ASSERT_EQ(bakegi_web_export(scene.get(), nullptr, folder.string().c_str(), nullptr), BAKEGI_OK)
      << bakegi_last_error();
  std::ifstream json_file(folder / "scene.gltf");
  const std::string json((std::istreambuf_iterator<char>(json_file)), {});
  EXPECT_NE(json.find("\"see_through\":{\"opacity\":1,\"transmission\":0.75}"), std::string::npos)
      << json.substr(0, 2000);
  EXPECT_NE(json.find("\"see_through\":{\"opacity\":0.5,\"transmission\":0,\"opacity_texture\":0}"),
            std::string::npos);
  EXPECT_EQ(json.find("\"see_through\":{\"opacity\":1,\"transmission\":0}"), std::string::npos)
      << "the opaque grey has no see-through part";
  int width = 0, height = 0, channels = 0;
  const std::string png = (folder / "opacity_2.png").string();
  unsigned char* pixels = stbi_load(png.c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr) << png;
  EXPECT_EQ(width, 2);
  EXPECT_EQ(height, 1);
  EXPECT_EQ(pixels[0], 0);    // the hole
  EXPECT_EQ(pixels[3], 128);  // 0.5 x 1 of 255, linear
  EXPECT_EQ(pixels[4], 128);  // three.js reads the green channel
  stbi_image_free(pixels);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace bakegi
