// The cells light sampling picks on emissive triangles (scene/triangle_cells.h,
// scene/emission_cells.h): the subdivision partitions a triangle into equal cells and finds
// the cell of any point; untextured emitters are one cell of their emission, exactly as
// before textures; textured ones follow their texture; the limits bound cells and lookups.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "light_transport_fixtures.h"
#include "scene/emission_cells.h"
#include "scene/triangle_cells.h"
#include "util/random.h"

namespace bakegi {
namespace {

TEST(TriangleCells, PartitionTheTriangleIntoEqualCellsAndFindThem) {
  Pcg32 rng(3, 5);
  for (uint32_t level = 1; level <= 9; ++level) {
    double area = 0.0;
    for (uint32_t cell = 0; cell < triangle_cell_count(level); ++cell) {
      const auto c = triangle_cell_corners(level, cell);
      for (const glm::vec2& p : c) {
        EXPECT_GE(p.x, 0.0f);
        EXPECT_GE(p.y, 0.0f);
        EXPECT_LE(p.x + p.y, 1.0f + 1e-6f);
      }
      const glm::vec2 e1 = c[1] - c[0], e2 = c[2] - c[0];
      const double cell_area = 0.5 * (double(e1.x) * e2.y - double(e1.y) * e2.x);
      // Equal and positively oriented: 1/level² of the unit triangle's 1/2.
      EXPECT_NEAR(cell_area, 0.5 / (level * level), 1e-7) << level << " " << cell;
      area += cell_area;
      for (int k = 0; k < 20; ++k) {
        // Keep clear of the edges, where float rounding may pick the neighbour.
        glm::vec2 s(rng.next_float(), rng.next_float());
        if (s.x + s.y > 1.0f) s = glm::vec2(1.0f) - s;
        s = glm::vec2(0.01f) + 0.97f * s;
        const glm::vec2 b = triangle_cell_point(level, c, s);
        EXPECT_EQ(triangle_cell_containing(level, b.x, b.y), cell) << level << " " << cell;
      }
    }
    EXPECT_NEAR(area, 0.5, 1e-6) << level;
  }
  // Level 1 is the triangle itself, bit for bit (untextured emitters sample as before).
  const glm::vec2 s(0.123456f, 0.654321f);
  const glm::vec2 b = triangle_cell_point(1, triangle_cell_corners(1, 0), s);
  EXPECT_EQ(b.x, s.x);
  EXPECT_EQ(b.y, s.y);
  // Points outside by rounding go to the nearest cell.
  EXPECT_LT(triangle_cell_containing(4, -1e-7f, 1.0f + 1e-7f), 16u);
  EXPECT_LT(triangle_cell_containing(4, 0.6f, 0.6f), 16u);
}

// One emitter quad, 1 x 1, its UVs spanning [0, uv_scale]² of a size x size texture whose
// left half (u < 0.5) is black and right half white (size 0: untextured).
SceneDescription emitter_quad(const glm::vec3& emission, int size, float uv_scale) {
  SceneDescription d;
  const uint32_t material = test::add_material(d, glm::vec3(0.0f), emission, true);
  if (size > 0) {
    d.materials[material].emission_texture = test::add_texture(
        d, uint32_t(size), uint32_t(size),
        [&](uint32_t i, uint32_t) { return glm::vec3(2 * int(i) >= size ? 1.0f : 0.0f); });
    test::add_quad_with_uvs(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.5f, 0.5f, material,
                            glm::vec2(0.0f), glm::vec2(uv_scale));
  } else {
    test::add_quad(d, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.5f, 0.5f, material);
  }
  d.lights.push_back(test::point_light({0, 0, 1}, glm::vec3(1.0f)));
  return d;
}

TEST(EmissionCells, UntexturedEmittersAreOneCellOfTheirEmission) {
  const Scene scene = build_scene(emitter_quad(glm::vec3(1.0f, 2.0f, 0.5f), 0, 1.0f));
  ASSERT_EQ(scene.emissive_triangles.size(), 2u);
  EXPECT_EQ(scene.emission_cells.level, (std::vector<uint32_t>{1, 1}));
  EXPECT_EQ(scene.emission_cells.first, (std::vector<uint64_t>{0, 1, 2}));
  EXPECT_EQ(scene.emission_cells.power, (std::vector<float>{3.5f, 3.5f}));
}

TEST(EmissionCells, TexturedCellsFollowTheTexture) {
  // A 64 x 64 texture, black then white along u, once across the quad: each triangle
  // covers 2048 of its 4096 texels, so its level is ceil(sqrt(2048 / 4)) = 23. Cells wholly in one
  // half hold 0 or the emission's sum (3); cells across an edge something between, and the cells'
  // mean is the texture's mean, 1.5, up to the quadrature (a few 1e-3: the edges are sampled at 4-8
  // points per cell).
  const glm::vec3 emission(1.0f, 1.5f, 0.5f);
  const Scene scene = build_scene(emitter_quad(emission, 64, 1.0f));
  const EmissionCells& cells = scene.emission_cells;
  ASSERT_EQ(scene.emissive_triangles.size(), 2u);
  double sum = 0.0;
  for (size_t e = 0; e < 2; ++e) {
    const uint32_t level = cells.level[e];
    EXPECT_EQ(level, 23u);
    ASSERT_EQ(cells.first[e + 1] - cells.first[e], uint64_t(level * level));
    const Triangle& t = scene.triangles[scene.emissive_triangles[e]];
    for (uint32_t c = 0; c < level * level; ++c) {
      const float power = cells.power[cells.first[e] + c];
      sum += power;
      const auto corners = triangle_cell_corners(level, c);
      float u_min = 1.0f, u_max = 0.0f;
      for (const glm::vec2& b : corners) {
        const float u = ((1.0f - b.x - b.y) * t.uv[0] + b.x * t.uv[1] + b.y * t.uv[2]).x;
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
      }
      // Bilinear filtering blends over half a texel either side of the edges at u = 0.5
      // and at u = 0 = 1 (repeat).
      const float blur = 0.5f / 64.0f;
      if (u_min > 0.5f + blur && u_max < 1.0f - blur) EXPECT_FLOAT_EQ(power, 3.0f);
      if (u_min > blur && u_max < 0.5f - blur) EXPECT_EQ(power, 0.0f);
    }
  }
  EXPECT_NEAR(sum / double(cells.power.size()), 1.5, 1.5 * 5e-3);
  EXPECT_EQ(build_emission_cells(scene), cells);  // deterministic
}

TEST(EmissionCells, LimitsBoundCellsAndLookups) {
  // UVs repeating the texture 100 times over the quad: every triangle would want level
  // 64 (the cap) and 8 x 8 lookups per cell. Limits shrink both evenly.
  const Scene scene = build_scene(emitter_quad(glm::vec3(1.0f), 64, 100.0f));
  EXPECT_EQ(scene.emission_cells.level, (std::vector<uint32_t>{64, 64}));
  EmissionCellLimits limits;
  limits.max_cells = 2000;
  limits.max_lookups = 20000;
  const EmissionCells small = build_emission_cells(scene, limits);
  uint64_t cells = 0;
  for (uint32_t level : small.level) cells += uint64_t(level) * level;
  EXPECT_LE(cells, limits.max_cells);
  EXPECT_GT(cells, limits.max_cells / 2);
  EXPECT_EQ(small.power.size(), cells);
  EXPECT_LE(small.lookups, limits.max_lookups);
  EXPECT_GT(small.lookups, limits.max_lookups / 4);
  EXPECT_GT(scene.emission_cells.lookups, small.lookups);
}

}  // namespace
}  // namespace bakegi
