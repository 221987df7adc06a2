// Texel samples that share a value: the samples one texel gets from the triangles of one flat
// surface share; samples of two charts packed into one texel, or of two faces meeting at a
// crease, do not; every group's first sample names itself and every name is earlier.
#include <array>

#include <gtest/gtest.h>

#include "lightmap/texel_rasterizer.h"
#include "lightmap/texel_sharing.h"
#include "scene/scene_validation.h"

namespace bakegi::test {
namespace {

// A triangle with world position `origin` + (u, v, 0) * scale: on a z = const plane.
LightmapTriangle mapped(glm::vec2 a, glm::vec2 b, glm::vec2 c, glm::vec3 origin, float scale) {
  LightmapTriangle t;
  const glm::vec2 uv[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    t.uv[k] = uv[k];
    t.p[k] = origin + glm::vec3(uv[k].x * scale, uv[k].y * scale, 0.0f);
    t.n[k] = glm::vec3(0.0f);  // face normal
  }
  return t;
}

// Samples that name another sample.
size_t shared_samples(const std::vector<uint32_t>& candidates) {
  size_t shared = 0;
  for (size_t i = 0; i < candidates.size(); ++i) shared += candidates[i] != i;
  return shared;
}

TEST(TexelSharing, SamplesOfOneFlatSurfaceInATexelShare) {
  // A quad of many thin triangles (a fan of 16 slivers) under an 8 x 8 lightmap: most texels
  // hold several samples, all on the z = 0 plane.
  std::vector<LightmapTriangle> triangles;
  const glm::vec2 centre(0.5f, 0.5f);
  const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int side = 0; side < 4; ++side) {
    for (int k = 0; k < 4; ++k) {
      const glm::vec2 a = glm::mix(corners[side], corners[(side + 1) % 4], k / 4.0f);
      const glm::vec2 b = glm::mix(corners[side], corners[(side + 1) % 4], (k + 1) / 4.0f);
      triangles.push_back(mapped(a, b, centre, glm::vec3(0.0f), 2.0f));
    }
  }
  const TexelSamples samples = rasterize_texels(triangles, 8, 8, 0);
  ASSERT_GT(samples.size(), 64u);
  const std::vector<uint32_t> candidates = texel_share_candidates(samples, 0);
  ASSERT_EQ(candidates.size(), samples.size());
  EXPECT_NO_THROW(check_share_candidates(candidates, candidates.size()));
  // One group per texel: every texel's extra samples share its first.
  EXPECT_EQ(samples.size() - shared_samples(candidates), samples.covered_texels());
  for (size_t i = 0; i < candidates.size(); ++i) {
    EXPECT_EQ(samples.texel[candidates[i]], samples.texel[i]);
  }
}

TEST(TexelSharing, ChartsPackedIntoOneTexelStayApart) {
  // Two charts that meet in UV at u = 0.4375 (texel column 3 of 8 holds samples of both)
  // but lie 10 m apart in the world, both flat and facing +z.
  std::vector<LightmapTriangle> triangles = {
      mapped({0.0f, 0.0f}, {0.4375f, 0.0f}, {0.4375f, 1.0f}, glm::vec3(0.0f), 2.0f),
      mapped({0.0f, 0.0f}, {0.4375f, 1.0f}, {0.0f, 1.0f}, glm::vec3(0.0f), 2.0f),
      mapped({0.4375f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, glm::vec3(10.0f, 0.0f, 0.0f), 2.0f),
      mapped({0.4375f, 0.0f}, {1.0f, 1.0f}, {0.4375f, 1.0f}, glm::vec3(10.0f, 0.0f, 0.0f), 2.0f),
  };
  const TexelSamples samples = rasterize_texels(triangles, 8, 8, 0);
  const std::vector<uint32_t> candidates = texel_share_candidates(samples, 0);
  EXPECT_NO_THROW(check_share_candidates(candidates, candidates.size()));
  for (size_t i = 0; i < candidates.size(); ++i) {
    const float apart = glm::length(samples.points.positions[i] -
                                    samples.points.positions[candidates[i]]);
    EXPECT_LT(apart, 1.0f) << "sample " << i << " shares with one " << apart << " m away";
  }
  // The diagonals inside each chart still share.
  EXPECT_GT(shared_samples(candidates), 0u);
}

TEST(TexelSharing, ACreaseInsideATexelStaysApart) {
  // Two faces meeting at v = 0.5 at a right angle: texels on the fold hold samples of both.
  std::vector<LightmapTriangle> triangles = {
      mapped({0, 0}, {1, 0}, {1, 0.5f}, glm::vec3(0.0f), 2.0f),
      mapped({0, 0}, {1, 0.5f}, {0, 0.5f}, glm::vec3(0.0f), 2.0f),
  };
  // The upper half folded up by 90 degrees about the line v = 0.5.
  for (const auto& [a, b, c] : {std::array<glm::vec2, 3>{glm::vec2(0, 0.5f), glm::vec2(1, 0.5f),
                                                          glm::vec2(1, 1)},
                                std::array<glm::vec2, 3>{glm::vec2(0, 0.5f), glm::vec2(1, 1),
                                                          glm::vec2(0, 1)}}) {
    LightmapTriangle t = mapped(a, b, c, glm::vec3(0.0f), 2.0f);
    for (glm::vec3& p : t.p) p = glm::vec3(p.x, 1.0f, p.y - 1.0f);
    triangles.push_back(t);
  }
  // 5 rows: row 2 spans v in [0.4, 0.6], across the fold.
  const TexelSamples samples = rasterize_texels(triangles, 5, 5, 0);
  const std::vector<uint32_t> candidates = texel_share_candidates(samples, 7);
  size_t across = 0;  // samples of the fold's texels on the upper face
  for (size_t i = 0; i < candidates.size(); ++i) {
    across += samples.texel[i] / 5 == 2 && samples.points.normals[i].z == 0.0f;
    const uint32_t c = candidates[i] - 7;
    EXPECT_GT(glm::dot(samples.points.normals[i], samples.points.normals[c]), 0.99f);
  }
  EXPECT_GT(across, 0u) << "no texel holds samples of both faces: the test tests nothing";
}

}  // namespace
}  // namespace bakegi::test
