// Resolving samples into texels (coverage-weighted means) and dilating into the gutters: no
// texel within the padding of a lit one reads zero, values come from the neighbours, and
// texels beyond the padding stay untouched.
#include <algorithm>
#include <cstdlib>

#include <gtest/gtest.h>

#include "lightmap/lightmap_padding.h"

namespace bakegi::test {
namespace {

TexelSamples empty_samples(uint32_t width, uint32_t height) {
  TexelSamples s;
  s.width = width;
  s.height = height;
  s.covered.assign(size_t(width) * height, 0);
  return s;
}

void add_sample(TexelSamples& s, uint32_t x, uint32_t y, float weight) {
  s.texel.push_back(y * s.width + x);
  s.weight.push_back(weight);
  s.covered[y * s.width + x] = 1;
}

TEST(LightmapPadding, ResolveIsTheCoverageWeightedMean) {
  TexelSamples s = empty_samples(2, 1);
  add_sample(s, 0, 0, 0.25f);
  add_sample(s, 0, 0, 0.75f);
  const std::vector<glm::vec3> values = {glm::vec3(0.0f), glm::vec3(4.0f, 8.0f, 12.0f)};
  std::vector<uint8_t> filled;
  const RgbImage image = resolve_texels(s, values.data(), filled);
  EXPECT_EQ(image.pixels[0], glm::vec3(3.0f, 6.0f, 9.0f));  // exact in binary
  EXPECT_EQ(image.pixels[1], glm::vec3(0.0f));
  EXPECT_EQ(filled, (std::vector<uint8_t>{1, 0}));
}

TEST(LightmapPadding, OneLitTexelSpreadsExactlyPaddingTexels) {
  TexelSamples s = empty_samples(9, 9);
  add_sample(s, 3, 4, 1.0f);
  const glm::vec3 light(1.0f, 2.0f, 3.0f);
  std::vector<uint8_t> filled;
  RgbImage image = resolve_texels(s, &light, filled);
  dilate_texels(image, filled, 2);
  for (int y = 0; y < 9; ++y) {
    for (int x = 0; x < 9; ++x) {
      const int distance = std::max(std::abs(x - 3), std::abs(y - 4));  // chessboard
      const glm::vec3 v = image.pixels[y * 9 + x];
      if (distance <= 2) {
        // Every neighbour it averages carries the one value: a copy (rounding of a mean of
        // equal floats: within 1 ulp).
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], light[c], 1e-6f) << x << "," << y;
        EXPECT_EQ(filled[y * 9 + x], 1);
      } else {
        EXPECT_EQ(v, glm::vec3(0.0f)) << x << "," << y;
        EXPECT_EQ(filled[y * 9 + x], 0);
      }
    }
  }
}

// A chart covering the left half with a vertical gradient: the gutter to its right reads the
// gradient (rows stay apart: each row's value comes from its own and adjacent rows), and no
// gutter texel within the padding is zero.
TEST(LightmapPadding, GutterNextToAChartIsFilledFromIt) {
  const uint32_t w = 12, h = 6, padding = 4;
  TexelSamples s = empty_samples(w, h);
  std::vector<glm::vec3> values;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < 5; ++x) {
      add_sample(s, x, y, 1.0f);
      values.push_back(glm::vec3(1.0f + y));
    }
  }
  std::vector<uint8_t> filled;
  RgbImage image = resolve_texels(s, values.data(), filled);
  dilate_texels(image, filled, padding);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 5; x < w; ++x) {
      const float v = image.pixels[y * w + x].x;
      if (x < 5 + padding) {
        EXPECT_GT(v, 0.0f) << x << "," << y;
        // Within the range of the rows it can reach (at most x - 4 rows away).
        const float reach = float(x - 4);
        EXPECT_GE(v, 1.0f + std::max(0.0f, float(y) - reach) - 1e-5f);
        EXPECT_LE(v, 1.0f + std::min(float(h - 1), float(y) + reach) + 1e-5f);
      } else {
        EXPECT_EQ(v, 0.0f) << x << "," << y;
      }
    }
  }
}

TEST(LightmapPadding, HoleInsideAChartIsFilled) {
  TexelSamples s = empty_samples(3, 3);
  std::vector<glm::vec3> values;
  for (uint32_t t = 0; t < 9; ++t) {
    if (t == 4) continue;  // the centre texel's samples were rejected
    add_sample(s, t % 3, t / 3, 1.0f);
    values.push_back(glm::vec3(2.0f));
  }
  std::vector<uint8_t> filled;
  RgbImage image = resolve_texels(s, values.data(), filled);
  EXPECT_EQ(image.pixels[4], glm::vec3(0.0f));
  dilate_texels(image, filled, 1);
  EXPECT_NEAR(image.pixels[4].y, 2.0f, 1e-6f);
}

}  // namespace
}  // namespace bakegi::test
