// Texel bake points: a quad covering the UV square bakes every texel, a half-square triangle
// bakes the texels whose centre it holds plus the half-covered diagonal ones (weights 1/2),
// partly covered edge texels are baked with samples on the triangle, texels outside every
// triangle are not, coverage weights add up to the UV area exactly, and degenerate triangles
// are skipped and counted.
#include <cmath>

#include <gtest/gtest.h>

#include "lightmap/texel_rasterizer.h"
#include "util/error.h"

namespace bakegi::test {
namespace {

// A planar triangle whose world position is (2u, v, 0): world and UV map affinely, so a
// sample's world position tells its UV point.
LightmapTriangle planar(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
  LightmapTriangle t;
  const glm::vec2 uv[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    t.uv[k] = uv[k];
    t.p[k] = glm::vec3(2.0f * uv[k].x, uv[k].y, 0.0f);
    t.n[k] = glm::vec3(0.0f);  // face normal
  }
  return t;
}

bool inside(glm::vec2 p, const LightmapTriangle& t) {
  auto edge = [](glm::vec2 a, glm::vec2 b, glm::vec2 q) {
    return (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
  };
  const float e0 = edge(t.uv[0], t.uv[1], p), e1 = edge(t.uv[1], t.uv[2], p),
              e2 = edge(t.uv[2], t.uv[0], p);
  return (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
}

std::vector<double> weight_per_texel(const TexelSamples& s) {
  std::vector<double> w(size_t(s.width) * s.height, 0.0);
  for (size_t i = 0; i < s.size(); ++i) w[s.texel[i]] += s.weight[i];
  return w;
}

// The memory check's bound must never be below the samples really made (else a budget
// check passes and the allocation does not fit), and not wildly above them for ordinary
// triangles (else sensible lightmaps are refused).
TEST(LightmapRasterizer, SampleBoundHoldsForRandomTriangles) {
  uint32_t state = 12345;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<LightmapTriangle> triangles;
    const int count = 1 + trial % 5;
    for (int i = 0; i < count; ++i) {
      // Some corners outside [0,1]^2, to exercise the clipping.
      auto uv = [&] { return glm::vec2(next() * 1.4f - 0.2f, next() * 1.4f - 0.2f); };
      triangles.push_back(planar(uv(), uv(), uv()));
    }
    const uint32_t width = 5 + trial % 40, height = 3 + (trial * 7) % 37;
    const TexelSamples samples = rasterize_texels(triangles, width, height);
    const uint64_t bound = max_texel_samples(triangles, width, height);
    EXPECT_GE(bound, samples.size()) << "trial " << trial;
  }
  // A quad filling a 64 x 64 map: 2 x 64^2 ... plus the diagonal's texels actually made;
  // the bound adds the perimeter term, about 2.8 x 4 x 64 x 2, so within 40% here.
  const std::vector<LightmapTriangle> quad = {planar({0, 0}, {1, 0}, {1, 1}),
                                              planar({0, 0}, {1, 1}, {0, 1})};
  const TexelSamples samples = rasterize_texels(quad, 64, 64);
  EXPECT_LE(double(max_texel_samples(quad, 64, 64)), 1.4 * double(samples.size()));
}

TEST(LightmapRasterizer, QuadCoveringTheSquareBakesEveryTexel) {
  const std::vector<LightmapTriangle> quad = {planar({0, 0}, {1, 0}, {1, 1}),
                                              planar({0, 0}, {1, 1}, {0, 1})};
  const TexelSamples s = rasterize_texels(quad, 8, 8, 7);
  EXPECT_EQ(s.covered_texels(), 64u);
  // The diagonal splits the 8 diagonal texels in two; it meets the others only at corners.
  EXPECT_EQ(s.size(), 72u);
  const std::vector<double> w = weight_per_texel(s);
  for (size_t t = 0; t < w.size(); ++t) EXPECT_NEAR(w[t], 1.0, 1e-6) << "texel " << t;
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s.points.object_ids[i], 7u);
    EXPECT_EQ(s.points.normals[i], glm::vec3(0, 0, 1));
    // The texel centre's UV point, mapped to world (2u, v, 0).
    const uint32_t x = s.texel[i] % 8, y = s.texel[i] / 8;
    EXPECT_NEAR(s.points.positions[i].x, 2.0f * (x + 0.5f) / 8, 1e-6f);
    EXPECT_NEAR(s.points.positions[i].y, (y + 0.5f) / 8, 1e-6f);
  }
}

TEST(LightmapRasterizer, HalfSquareTriangle) {
  const std::vector<LightmapTriangle> tri = {planar({0, 0}, {1, 0}, {0, 1})};
  const TexelSamples s = rasterize_texels(tri, 8, 8);
  // Centres inside (x + y <= 7): 36 texels, of which the 8 on the diagonal are half covered.
  EXPECT_EQ(s.covered_texels(), 36u);
  EXPECT_EQ(s.size(), 36u);
  double total = 0;
  for (uint32_t y = 0; y < 8; ++y) {
    for (uint32_t x = 0; x < 8; ++x) {
      const size_t t = y * 8 + x;
      EXPECT_EQ(s.covered[t], x + y <= 7 ? 1 : 0) << x << "," << y;
    }
  }
  for (size_t i = 0; i < s.size(); ++i) {
    const uint32_t x = s.texel[i] % 8, y = s.texel[i] / 8;
    EXPECT_NEAR(s.weight[i], x + y == 7 ? 0.5 : 1.0, 1e-6);
    total += s.weight[i];
  }
  EXPECT_NEAR(total, 32.0, 1e-5);  // the triangle's area in texels
}

// A triangle whose edges cut texels away from their centres: every texel it touches with
// positive area is baked (checked against 32 x 32 sub-texel points), its samples lie on the
// triangle, and the weights add up to its area.
TEST(LightmapRasterizer, ConservativeAtEdgesAndOnlyThere) {
  const LightmapTriangle t = planar({0.1f, 0.13f}, {0.87f, 0.2f}, {0.23f, 0.91f});
  const TexelSamples s = rasterize_texels({t}, 8, 8);
  int partly_covered_baked = 0;
  for (uint32_t y = 0; y < 8; ++y) {
    for (uint32_t x = 0; x < 8; ++x) {
      bool touched = false;
      for (int j = 0; j < 32 && !touched; ++j) {
        for (int i = 0; i < 32 && !touched; ++i) {
          touched = inside({(x + (i + 0.5f) / 32) / 8, (y + (j + 0.5f) / 32) / 8}, t);
        }
      }
      const bool centre = inside({(x + 0.5f) / 8, (y + 0.5f) / 8}, t);
      const size_t texel = y * 8 + x;
      if (centre) EXPECT_EQ(s.covered[texel], 1) << "centre inside, not baked: " << x << "," << y;
      if (touched) EXPECT_EQ(s.covered[texel], 1) << "partly covered, not baked: " << x << "," << y;
      if (touched && !centre) ++partly_covered_baked;
      // A texel the sub-texel points all miss may still be grazed by a corner: allowed only
      // when tiny, so check the other way with the exact weight.
      if (!touched && s.covered[texel]) {
        EXPECT_LT(weight_per_texel(s)[texel], 1.0 / 512) << x << "," << y;
      }
    }
  }
  EXPECT_GT(partly_covered_baked, 5);  // the test exercises edge texels
  // Samples lie on the triangle (world = (2u, v, 0), so back to UV), even for edge texels.
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::vec2 uv(s.points.positions[i].x / 2, s.points.positions[i].y);
    // Allow float rounding of a point clamped onto an edge.
    const glm::vec2 centroid = (t.uv[0] + t.uv[1] + t.uv[2]) / 3.0f;
    EXPECT_TRUE(inside(uv + 1e-5f * glm::normalize(centroid - uv + 1e-9f), t))
        << "sample " << i << " off the triangle";
  }
  const double area_in_texels = 0.5 *
                                std::abs((t.uv[1].x - t.uv[0].x) * (t.uv[2].y - t.uv[0].y) -
                                         (t.uv[2].x - t.uv[0].x) * (t.uv[1].y - t.uv[0].y)) *
                                64;
  double total = 0;
  for (float w : s.weight) total += w;
  EXPECT_NEAR(total, area_in_texels, 1e-5);
}

TEST(LightmapRasterizer, InterpolatesNormals) {
  LightmapTriangle t = planar({0, 0}, {1, 0}, {0, 1});
  t.n[0] = {0, 0, 1};
  t.n[1] = {1, 0, 1};  // not unit: normalized first
  t.n[2] = {0, 0, 2};
  const TexelSamples s = rasterize_texels({t}, 4, 4);
  for (size_t i = 0; i < s.size(); ++i) {
    const glm::vec3 n = s.points.normals[i];
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    const float b1 = s.points.positions[i].x / 2;  // u = weight of corner 1
    const glm::vec3 expected =
        glm::normalize((1 - b1) * glm::vec3(0, 0, 1) + b1 * glm::normalize(glm::vec3(1, 0, 1)));
    EXPECT_NEAR(glm::distance(n, expected), 0.0f, 1e-5f) << "sample " << i;
  }
}

TEST(LightmapRasterizer, SkipsDegenerateTrianglesAndClipsToTheMap) {
  std::vector<LightmapTriangle> tris = {
      planar({0.2f, 0.2f}, {0.6f, 0.6f}, {0.4f, 0.4f}),
      planar({0, 0}, {1, 0}, {0, 1}),
  };
  tris[0].p[2] = {0, 0, 1};  // a real triangle in space, with zero UV area
  LightmapTriangle flat = planar({0, 0}, {1, 0}, {0, 1});
  flat.p[1] = flat.p[2] = flat.p[0];  // zero world area
  tris.push_back(flat);
  tris.push_back(planar({-1, -1}, {3, -1}, {-1, 3}));  // covers the map and more
  const TexelSamples s = rasterize_texels(tris, 4, 4);
  EXPECT_EQ(s.skipped_degenerate_uv, 1u);
  EXPECT_EQ(s.skipped_degenerate_geometry, 1u);
  EXPECT_EQ(s.covered_texels(), 16u);
  EXPECT_THROW(rasterize_texels(tris, 0, 4), Error);
  tris[1].uv[0].x = NAN;
  EXPECT_THROW(rasterize_texels(tris, 4, 4), Error);
}

TEST(LightmapRasterizer, KeepSamplesUpdatesCoverage) {
  TexelSamples s =
      rasterize_texels({planar({0, 0}, {1, 0}, {1, 1}), planar({0, 0}, {1, 1}, {0, 1})}, 2, 2);
  ASSERT_EQ(s.size(), 6u);
  std::vector<bool> keep(s.size(), true);
  // Drop every sample of texel (1, 0) (one triangle covers it wholly).
  for (size_t i = 0; i < s.size(); ++i) keep[i] = s.texel[i] != 1;
  keep_samples(s, keep);
  EXPECT_EQ(s.size(), 5u);
  EXPECT_EQ(s.covered[1], 0);
  EXPECT_EQ(s.covered_texels(), 3u);
  EXPECT_EQ(s.points.positions.size(), 5u);
  EXPECT_EQ(s.face_normals.size(), 5u);
}

}  // namespace
}  // namespace bakegi::test
