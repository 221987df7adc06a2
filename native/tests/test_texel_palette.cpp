// TexelPalette: a texture of at most 256 distinct channel values is read through 8-bit indices,
// and every lookup returns exactly what the float texels hold (bakes stay bit for bit the same).
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "scene/texel_palette.h"

namespace bakegi::test {
namespace {

// An 8-bit image's 256 levels, linearised as the add-on does (sRGB, IEC 61966-2-1).
std::vector<float> srgb_levels() {
  std::vector<float> levels;
  for (int k = 0; k < 256; ++k) {
    const double c = k / 255.0;
    levels.push_back(float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4)));
  }
  return levels;
}

std::vector<glm::vec3> random_texels(size_t count, const std::vector<float>& levels,
                                     uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, levels.size() - 1);
  std::vector<glm::vec3> texels(count);
  for (glm::vec3& t : texels) t = {levels[pick(rng)], levels[pick(rng)], levels[pick(rng)]};
  return texels;
}

TEST(TexelPalette, HoldsEveryTexelExactly) {
  const std::vector<glm::vec3> texels = random_texels(64 * 32, srgb_levels(), 3);
  const auto palette = make_texel_palette(texels);
  ASSERT_NE(palette, nullptr);
  for (size_t i = 0; i < texels.size(); ++i) {
    const glm::vec3 read = palette->texel(i);
    for (int c = 0; c < 3; ++c) {
      // Bit for bit: -0.0 and 0.0 or two NaNs would differ here.
      EXPECT_EQ(std::memcmp(&read[c], &texels[i][c], sizeof(float)), 0) << i;
    }
  }
  EXPECT_EQ(palette->bytes(), 256 * sizeof(float) + 3 * texels.size());
}

TEST(TexelPalette, MoreThan256ValuesKeepTheFloats) {
  std::vector<float> levels = srgb_levels();
  std::vector<glm::vec3> texels = random_texels(4096, levels, 4);
  texels.push_back(glm::vec3(0.123456f));  // a 257th value
  EXPECT_EQ(make_texel_palette(texels), nullptr);
  // Bit patterns count, not values: 0.0 and -0.0 are two entries.
  std::vector<glm::vec3> zeros{glm::vec3(0.0f), glm::vec3(-0.0f)};
  const auto palette = make_texel_palette(zeros);
  ASSERT_NE(palette, nullptr);
  EXPECT_TRUE(std::signbit(palette->texel(1).x));
  EXPECT_FALSE(std::signbit(palette->texel(0).x));
}

// Scene::albedo_at reads the palette where there is one: the same bilinear values as the floats.
TEST(TexelPalette, AlbedoLookupsAgreeWithTheFloats) {
  SceneDescription d;
  Texture texture;
  texture.width = 37;
  texture.height = 23;
  texture.set_texels(random_texels(37 * 23, srgb_levels(), 5));
  ASSERT_NE(texture.palette(), nullptr);
  Texture floats = texture;
  floats.set_texels(texture.texels(), false);
  ASSERT_EQ(floats.palette(), nullptr);
  ASSERT_NE(floats.float_texels(), nullptr);
  EXPECT_TRUE(floats == texture);  // equal texels, held two ways
  EXPECT_EQ(texture.bytes(), 256 * sizeof(float) + 3 * 37 * 23);
  EXPECT_EQ(floats.bytes(), 12 * 37 * 23);
  d.textures = {texture, floats};
  Material material;
  material.albedo = glm::vec3(0.9f);
  material.albedo_texture = 0;
  d.materials.push_back(material);
  material.albedo_texture = 1;
  d.materials.push_back(material);
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.indices = {0, 1, 2, 0, 1, 3};
  mesh.corner_uvs = {{-0.3f, 0.1f}, {2.7f, 0.4f}, {0.2f, -1.9f},
                     {-0.3f, 0.1f}, {2.7f, 0.4f}, {0.2f, -1.9f}};
  mesh.triangle_materials = {0, 1};
  d.meshes.push_back(mesh);
  Light light;
  light.color = glm::vec3(1.0f);
  d.lights.push_back(light);
  const Scene scene = build_scene(d);
  ASSERT_EQ(scene.triangles.size(), 2u);
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int n = 0; n < 2000; ++n) {
    float b1 = unit(rng), b2 = unit(rng);
    if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
    EXPECT_EQ(scene.albedo_at(0u, b1, b2), scene.albedo_at(1u, b1, b2)) << n;
  }
}

}  // namespace
}  // namespace bakegi::test
