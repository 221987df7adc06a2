// UV seams: found where a mesh's two charts meet (and only there), kept through add_to and
// the layout file, and stitched by bakegi_lightmaps_write_exr so that bilinear lookups on
// both sides of a seam read the same light; texels away from seams, and lightmaps without
// seams, are written exactly as before.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include "lightmap/lightmap_layout_file.h"
#include "lightmap/lightmap_seams.h"
#include "bakegi/bakegi.h"
#include "bakegi/bakegi_handles.hpp"
#include "lightmap_test_scene.h"
#include "lightmap/exr_writer.h"
#include "lightmap/lightmap_padding.h"
#include "lightmap/seam_stitching.h"

namespace bakegi::test {
namespace {

// The strip's triangles as the rasterizer and the seam finder take them.
std::vector<LightmapTriangle> strip_triangles(const Strip& strip, const std::vector<float>& uvs) {
  std::vector<LightmapTriangle> triangles(strip.indices.size() / 3);
  for (size_t corner = 0; corner < strip.indices.size(); ++corner) {
    LightmapTriangle& tri = triangles[corner / 3];
    const uint32_t v = strip.indices[corner];
    tri.p[corner % 3] = {strip.positions[3 * v], strip.positions[3 * v + 1],
                         strip.positions[3 * v + 2]};
    tri.n[corner % 3] = glm::vec3(0.0f);  // face normals
    tri.uv[corner % 3] = {uvs[2 * corner], uvs[2 * corner + 1]};
  }
  return triangles;
}

constexpr uint32_t kSize = 32;  // texels per side of the test lightmaps
// Two charts in a 32 x 32 map: the left quad on texels [2.5, 12.5] x [3, 13], the right one
// larger and off the texel grid, on [17.3, 29.8] x [4.6, 17.1]: the two sides of the seam
// sample the surface at different places.
const glm::vec2 kLeftOrigin(2.5f / kSize, 3.0f / kSize), kRightOrigin(17.3f / kSize, 4.6f / kSize);
constexpr float kLeftScale = 10.0f / kSize, kRightScale = 12.5f / kSize;

std::vector<float> two_chart_uvs(const Strip& strip) {
  return strip.uvs(kLeftOrigin, kLeftScale, kRightOrigin, kRightScale);
}
std::vector<float> one_chart_uvs(const Strip& strip) {
  return strip.uvs(kLeftOrigin, kLeftScale, kLeftOrigin + glm::vec2(kLeftScale, 0), kLeftScale);
}

// The shared edge's UVs on each side at height t (vertex 1 at t = 0, vertex 4 at t = 1).
glm::vec2 left_side(float t) {
  return kLeftOrigin + kLeftScale * glm::vec2(1, t);
}
glm::vec2 right_side(float t) {
  return kRightOrigin + kRightScale * glm::vec2(0, t);
}

TEST(LightmapSeams, TwoChartsMeetAtExactlyTheSharedEdge) {
  const Strip strip;
  const std::vector<LightmapSeam> seams = find_lightmap_seams(
      strip.indices, strip_triangles(strip, two_chart_uvs(strip)), kSize, kSize);
  ASSERT_EQ(seams.size(), 1u);  // not the quads' diagonals, not the borders
  const LightmapSeam& seam = seams[0];
  // Endpoint k of both sides is one vertex: {vertex 1, vertex 4} in some order, the left
  // chart's UVs on one side and the right chart's on the other.
  const bool left_is_a = std::abs(seam.a[0].x - left_side(0).x) < 1e-6f;
  const glm::vec2* left = left_is_a ? seam.a : seam.b;
  const glm::vec2* right = left_is_a ? seam.b : seam.a;
  const bool vertex_1_first = std::abs(left[0].y - left_side(0).y) < 1e-6f;
  for (int k = 0; k < 2; ++k) {
    const float t = (k == 0) == vertex_1_first ? 0.0f : 1.0f;
    EXPECT_NEAR(glm::length(left[k] - left_side(t)), 0.0f, 1e-6f) << k;
    EXPECT_NEAR(glm::length(right[k] - right_side(t)), 0.0f, 1e-6f) << k;
  }
}

TEST(LightmapSeams, OneChartHasNone) {
  const Strip strip;
  EXPECT_TRUE(
      find_lightmap_seams(strip.indices, strip_triangles(strip, one_chart_uvs(strip)), kSize, kSize)
          .empty());
}

// A fold (the right quad turned up by 90 degrees: a real edge in the light) and an edge
// shared by three triangles are not seams, even with the UVs of two charts.
TEST(LightmapSeams, FoldsAndNonManifoldEdgesAreNotSeams) {
  Strip folded;
  for (uint32_t v : {2u, 5u}) {  // (2, y, 0) -> (1, y, 1)
    folded.positions[3 * v] = 1;
    folded.positions[3 * v + 2] = 1;
  }
  // UVs of the flat strip: folding moves no UV (and leaves no triangle degenerate).
  EXPECT_TRUE(find_lightmap_seams(folded.indices, strip_triangles(folded, two_chart_uvs(Strip())),
                                  kSize, kSize)
                  .empty());

  Strip fin;  // a third triangle (1, 4, 6) on the shared edge, standing below it
  fin.positions.insert(fin.positions.end(), {1.0f, 0.5f, -1.0f});
  fin.indices.insert(fin.indices.end(), {1, 4, 6});
  std::vector<float> uvs = two_chart_uvs(fin);  // the fin's UVs: a third chart
  uvs.resize(uvs.size() - 6);
  uvs.insert(uvs.end(), {0.1f, 0.8f, 0.3f, 0.8f, 0.2f, 0.9f});
  EXPECT_TRUE(find_lightmap_seams(fin.indices, strip_triangles(fin, uvs), kSize, kSize).empty());
}

// Blender's Linear interpolation of an image held bottom-up: texel centres at
// (i + 0.5) / W, clamped at the border. Written here again, not taken from the writer, so
// that the test checks the convention and not the code against itself.
glm::vec3 linear_lookup(const RgbImage& image, glm::vec2 uv) {
  const auto axis = [](float c, uint32_t size, uint32_t& low, uint32_t& high, float& f) {
    const float x = std::clamp(c * float(size) - 0.5f, 0.0f, float(size - 1));
    low = uint32_t(x);
    high = std::min(low + 1, size - 1);
    f = x - float(low);
  };
  uint32_t x0, x1, y0, y1;
  float fx, fy;
  axis(uv.x, image.width, x0, x1, fx);
  axis(uv.y, image.height, y0, y1, fy);
  const auto at = [&](uint32_t x, uint32_t y) { return image.pixels[size_t(y) * image.width + x]; };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
         fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

float largest_component(const glm::vec3& v) {
  return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

// The largest difference between the two sides' lookups along the seam, at 401 points.
float seam_mismatch(const RgbImage& image) {
  float largest = 0;
  for (int i = 0; i <= 400; ++i) {
    const float t = float(i) / 400;
    largest = std::max(largest, largest_component(linear_lookup(image, left_side(t)) -
                                                  linear_lookup(image, right_side(t))));
  }
  return largest;
}

// Distance (texels) from texel (x, y)'s centre to the segment a-b (UVs).
float texel_distance(uint32_t x, uint32_t y, glm::vec2 a, glm::vec2 b) {
  const glm::vec2 p(x + 0.5f, y + 0.5f), pa = a * float(kSize), pb = b * float(kSize);
  const float s = std::clamp(glm::dot(p - pa, pb - pa) / glm::dot(pb - pa, pb - pa), 0.0f, 1.0f);
  return glm::length(p - (pa + s * (pb - pa)));
}

class LightmapSeamStitching : public LightmapFilesTest {
 protected:
  // Adds the strip with `uvs` to a lit scene and a 32 x 32 lightmap, and makes the bake
  // result a smooth linear function of position (a gradient across the seam, as light
  // near it is, to first order): then each side's texels hold that function at their own
  // samples, and a mismatch along the seam comes from where the samples lie, nothing else.
  void bake_strip(const std::vector<float>& uvs) {
    scene_ = lit_scene();
    const uint32_t mesh = strip_.add_to(scene_.get(), 1);
    lightmaps_ = new_lightmaps();
    ASSERT_EQ(bakegi_lightmaps_add(lightmaps_.get(), scene_.get(), mesh, uvs.data(), kSize, kSize,
                                   nullptr),
              BAKEGI_OK)
        << bakegi_last_error();
    bakegi_points* raw = nullptr;
    ASSERT_EQ(bakegi_lightmaps_get_points(lightmaps_.get(), &raw), BAKEGI_OK);
    const PointsHandle points(raw);
    const uint64_t count = bakegi_points_count(points.get());
    std::vector<float> positions(3 * count);
    ASSERT_EQ(bakegi_points_get(points.get(), positions.data(), nullptr, nullptr), BAKEGI_OK);
    rgb_.resize(3 * count);
    for (uint64_t i = 0; i < count; ++i) {
      const float x = positions[3 * i], y = positions[3 * i + 1];
      rgb_[3 * i] = 0.2f + 0.5f * x + 0.25f * y;
      rgb_[3 * i + 1] = 0.4f + 0.3f * x - 0.2f * y;
      rgb_[3 * i + 2] = 1.0f - 0.25f * x + 0.1f * y;
    }
    // Stitched, through the C API; full floats, so that the file holds what was computed.
    ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps_.get(), 0, rgb_.data(), count,
                                         path("stitched.exr").c_str(), kPadding, 1, BAKEGI_EXR_ZIP),
              BAKEGI_OK)
        << bakegi_last_error();
    stitched_ = read_exr(path("stitched.exr"));
    // And what was written before stitching: resolved and dilated the same way.
    ASSERT_EQ(bakegi_lightmaps_write_file(lightmaps_.get(), path("layout.bgl").c_str()), BAKEGI_OK);
    layout_ = read_lightmap_layout_file(path("layout.bgl"));
    ASSERT_EQ(layout_.lightmaps.size(), 1u);
    unstitched_ = resolve_texels(layout_.lightmaps[0].samples,
                                 reinterpret_cast<const glm::vec3*>(rgb_.data()), filled_);
    dilate_texels(unstitched_, filled_, kPadding);
  }

  static constexpr uint32_t kPadding = 2;
  const Strip strip_;
  SceneHandle scene_;
  LightmapsPtr lightmaps_;
  std::vector<float> rgb_;
  LightmapLayout layout_;
  RgbImage stitched_, unstitched_;
  std::vector<uint8_t> filled_;  // the texels resolved or dilated
};

TEST_F(LightmapSeamStitching, BothSidesReadTheSameAlongTheSeam) {
  bake_strip(two_chart_uvs(strip_));
  ASSERT_EQ(layout_.lightmaps[0].seams.size(), 1u);
  ASSERT_EQ(stitched_.width, kSize);
  ASSERT_EQ(stitched_.pixels.size(), unstitched_.pixels.size());

  const float before = seam_mismatch(unstitched_), after = seam_mismatch(stitched_);
  // Unstitched, the sides differ by the gradient (0.5 per metre, 10 or 12.5 texels per
  // metre) times how far apart their samples and dilated texels lie, a fraction of a
  // texel: several hundredths.
  EXPECT_GT(before, 0.01f);
  // Stitched, they agree at the constraint points (every half texel, to 1e-4 of the
  // values ~1); between those, both sides are piecewise linear along the seam with kinks at
  // their own texel centres, which no set of points pins together: measured 4.8e-4. The
  // bound leaves 2x for rounding and sweep order, and is 25x under the mismatch before.
  EXPECT_LT(after, 1e-3f) << "before " << before;

  // Only texels within a footprint of a seam point move: centres closer than sqrt(2)
  // texels to the seam on either side. Everything else is bit for bit as before.
  size_t changed = 0;
  for (uint32_t y = 0; y < kSize; ++y) {
    for (uint32_t x = 0; x < kSize; ++x) {
      const size_t t = size_t(y) * kSize + x;
      if (stitched_.pixels[t] == unstitched_.pixels[t]) continue;
      ++changed;
      const float near = std::min(texel_distance(x, y, left_side(0), left_side(1)),
                                  texel_distance(x, y, right_side(0), right_side(1)));
      EXPECT_LT(near, 1.415f) << "texel " << x << ", " << y << " changed";
      // Unfilled texels (0, beyond the padding) stay 0.
      EXPECT_NE(unstitched_.pixels[t], glm::vec3(0.0f)) << "texel " << x << ", " << y;
    }
  }
  EXPECT_GT(changed, 10u);
}

// Solved in batches of a few points (as a huge atlas is), the seam is stitched as well:
// here the batches follow one another along one seam, each leaving the previous ones'
// points nearly satisfied (their footprints overlap by a texel at most).
TEST_F(LightmapSeamStitching, BatchesStitchToo) {
  bake_strip(two_chart_uvs(strip_));
  RgbImage batched = unstitched_;
  SeamStitchOptions options;
  options.batch_points = 4;
  const SeamStitchReport report = stitch_seams(batched, layout_.lightmaps[0].samples.covered,
                                               filled_, layout_.lightmaps[0].seams, options);
  EXPECT_GT(report.points, 20u);  // 25 texels of seam: 26 points, in 7 batches
  EXPECT_LT(report.mismatch_after, report.mismatch_before / 10);
  // Each batch disturbs the texels it shares with the one before: measured 8.3e-4 along
  // the seam, against 4.8e-4 in one batch and 2.5e-2 unstitched; the bound leaves 2x.
  EXPECT_LT(seam_mismatch(batched), 2e-3f) << "unstitched " << seam_mismatch(unstitched_);
}

TEST_F(LightmapSeamStitching, WithoutSeamsTheFileIsAsBefore) {
  bake_strip(one_chart_uvs(strip_));
  EXPECT_TRUE(layout_.lightmaps[0].seams.empty());
  ASSERT_EQ(stitched_.pixels.size(), unstitched_.pixels.size());
  for (size_t t = 0; t < stitched_.pixels.size(); ++t) {
    ASSERT_EQ(stitched_.pixels[t], unstitched_.pixels[t]) << "texel " << t;
  }
}

// Seams of meshes added to one atlas with add_to are kept in the atlas's UVs, after the
// first mesh's.
TEST_F(LightmapSeamStitching, AddToKeepsEachMeshsSeams) {
  const SceneHandle scene = lit_scene();
  const Strip lower(0), upper(2);
  const uint32_t first = lower.add_to(scene.get(), 1), second = upper.add_to(scene.get(), 2);
  const LightmapsPtr lightmaps = new_lightmaps();
  const std::vector<float> lower_uvs = two_chart_uvs(lower);
  std::vector<float> upper_uvs = two_chart_uvs(upper);
  for (size_t i = 1; i < upper_uvs.size(); i += 2) upper_uvs[i] = upper_uvs[i] * 0.5f + 0.5f;
  ASSERT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene.get(), first, lower_uvs.data(), kSize,
                                 kSize, nullptr),
            BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_add_to(lightmaps.get(), 0, scene.get(), second, upper_uvs.data()),
            BAKEGI_OK)
      << bakegi_last_error();
  ASSERT_EQ(bakegi_lightmaps_write_file(lightmaps.get(), path("atlas.bgl").c_str()), BAKEGI_OK);
  const LightmapLayout layout = read_lightmap_layout_file(path("atlas.bgl"));
  ASSERT_EQ(layout.lightmaps.size(), 1u);
  const std::vector<LightmapSeam>& seams = layout.lightmaps[0].seams;
  ASSERT_EQ(seams.size(), 2u);
  // The second seam lies in the upper half of the atlas, where add_to placed the mesh.
  for (const glm::vec2& uv : {seams[0].a[0], seams[0].a[1], seams[0].b[0], seams[0].b[1]}) {
    EXPECT_LT(uv.y, 0.6f);
  }
  for (const glm::vec2& uv : {seams[1].a[0], seams[1].a[1], seams[1].b[0], seams[1].b[1]}) {
    EXPECT_GE(uv.y, 0.5f);
  }
}

}  // namespace
}  // namespace bakegi::test
