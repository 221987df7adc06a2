// The Irradiance Vector Grid (native/src/grid/): layout, gathering against closed forms,
// push-pull, interpolation, quantization and the .bgivg file.
//
// Furnace: inside a closed enclosure whose walls all emit Le (two-sided) with albedo rho, the
// radiance is uniform, L = Le / (1 - rho), and the part surfaces reflect is L - Le =
// Le rho / (1 - rho) in every direction (test_pathtrace_sphere.cpp). Each hemisphere's
// irradiance vector is then I_delta = pi (L - Le) delta, and a receiver whose normal lies on
// an axis reads exactly L - Le (output convention E / pi).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "field/indirect_field.h"
#include "grid/grid_file.h"
#include "grid/grid_gather.h"
#include "grid/grid_hit_radiance.h"
#include "grid/grid_interpolation.h"
#include "grid/grid_layout.h"
#include "grid/grid_push_pull.h"
#include "grid/grid_quantization.h"
#include "light_transport_fixtures.h"
#include "solvers/pathtrace/path_trace_solver.h"
#include "util/error.h"
#include "util/pcg32.h"

namespace bakegi {
namespace {

constexpr float kRadius = 1.5f;

// An icosphere wound to face inwards (a closed room: rays from inside meet front faces).
Mesh inward_sphere(uint32_t material) {
  Mesh mesh = test::make_icosphere(glm::vec3(0.0f), kRadius, 3, material);
  for (size_t t = 0; t < mesh.indices.size(); t += 3)
    std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
  return mesh;
}

struct GatheredGrid {
  IrradianceVectorGrid grid;
  GridGatherStatistics statistics;
};

GatheredGrid gather(const SceneDescription& d, const GridLayout& layout, uint32_t rays,
                    const IndirectField* field = nullptr) {
  const Scene scene = build_scene(d);
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  Settings settings;
  settings.set("max_bounces", int64_t(64));
  const PathTracedField paths(direct, PathTraceSettings::from(settings));
  const std::unique_ptr<HitRadiance> radiance = make_hit_radiance(direct, field ? *field : paths);
  GridGatherOptions options;
  options.rays_per_hemisphere = rays;
  options.ray_epsilon = direct.ray_epsilon();
  JobContext context;
  GatheredGrid out{IrradianceVectorGrid(layout), {}};
  out.grid = gather_grid(layout, scene, tracer, *radiance, options, context, out.statistics);
  return out;
}

TEST(GridLayout, CellSizeAndBudget) {
  const GridLayout fine = choose_grid_layout({0, 0, 0}, {4, 2, 1}, 0.25f, 1 << 20);
  EXPECT_EQ(fine.resolution, (std::array<uint32_t, 3>{16, 8, 4}));
  EXPECT_NEAR(fine.vertex_position(0, 0, 0).x, 0.125f, 1e-6f);  // cell centres
  // The budget coarsens evenly: at most 64 vertices.
  const GridLayout coarse = choose_grid_layout({0, 0, 0}, {4, 2, 1}, 0.25f, 64);
  EXPECT_LE(coarse.vertex_count(), 64u);
  EXPECT_GE(coarse.resolution[0], coarse.resolution[1]);
  // Default: 32 cells on the longest axis; a flat axis gets two vertices one cell apart.
  const GridLayout flat = choose_grid_layout({0, 0, 0}, {8, 4, 0}, 0.0f, 1 << 20);
  EXPECT_EQ(flat.resolution, (std::array<uint32_t, 3>{32, 16, 2}));
  EXPECT_NEAR(flat.bounds_max.z - flat.bounds_min.z, 0.5f, 1e-5f);
  EXPECT_THROW(choose_grid_layout({0, 0, 0}, {-1, 1, 1}, 0.1f, 1000), Error);
  EXPECT_THROW(choose_grid_layout({0, 0, 0}, {1, 1, NAN}, 0.1f, 1000), Error);
  EXPECT_THROW(choose_grid_layout({0, 0, 0}, {1, 1, 1}, -1.0f, 1000), Error);
  EXPECT_THROW(choose_grid_layout({0, 0, 0}, {0, 0, 0}, 0.1f, 1000), Error);
  EXPECT_THROW(choose_grid_layout({0, 0, 0}, {1, 1, 1}, 0.1f, 7), Error);
}

TEST(GridGather, FurnaceGivesTheClosedForm) {
  const float rho = 0.5f;
  const glm::vec3 emission(1.0f, 0.5f, 2.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, glm::vec3(rho), emission, true);
  d.meshes.push_back(inward_sphere(wall));
  const glm::vec3 expected = emission * (rho / (1.0f - rho));
  const GridLayout layout = make_grid_layout(glm::vec3(-0.8f), glm::vec3(0.8f), {3, 3, 3});
  const GatheredGrid g = gather(d, layout, 256);
  EXPECT_EQ(g.statistics.invalid_vertices, 0u);
  for (size_t v = 0; v < g.grid.vertex_count(); ++v) {
    for (int h = 0; h < kGridHemispheres; ++h) {
      const glm::mat3& m = g.grid.at(v, h);
      const glm::vec3 axis = hemisphere_axis(h);
      for (int c = 0; c < 3; ++c) {
        // 256 stratified rays of one-sample paths: a few percent each; 6% bound.
        EXPECT_NEAR(glm::dot(m[c], axis), kPi * expected[c], 0.06f * kPi * expected[c])
            << "vertex " << v << " hemisphere " << h << " channel " << c;
        // Sideways components cancel in uniform light.
        EXPECT_LT(glm::length(m[c] - axis * glm::dot(m[c], axis)), 0.08f * kPi * expected[c]);
      }
    }
  }
  // Any point inside, normal on an axis: the closed form; 45 degrees between two axes: the
  // paper's directional weights give sum n_a^2 |n_a| = 1/sqrt(2) of it.
  const glm::vec3 axis_value =
      evaluate_grid(g.grid, {0.1f, -0.2f, 0.3f}, {0, 0, -1}, GridInterpolation::kTrilinear);
  const glm::vec3 diagonal =
      evaluate_grid(g.grid, {0.1f, -0.2f, 0.3f}, {1, 1, 0}, GridInterpolation::kTricubic);
  // |n| weights: exact under uniform light whatever the normal.
  const glm::vec3 absolute =
      evaluate_grid(g.grid, {0.1f, -0.2f, 0.3f}, {1, -1, 1}, GridInterpolation::kTrilinear,
                    GridDirectionalWeights::kAbsolute);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(axis_value[c], expected[c], 0.03f * expected[c]) << c;
    EXPECT_NEAR(diagonal[c], expected[c] / std::sqrt(2.0f), 0.03f * expected[c]) << c;
    EXPECT_NEAR(absolute[c], expected[c], 0.03f * expected[c]) << c;
  }
  // The walls' own emission, seen straight: pi Le along each hemisphere's axis.
  ASSERT_TRUE(g.grid.has_emitted());
  for (size_t v = 0; v < g.grid.vertex_count(); ++v) {
    for (int h = 0; h < kGridHemispheres; ++h) {
      for (int c = 0; c < 3; ++c) {
        // A constant integrand: QMC's only error is the sideways rest of the Sobol' points.
        EXPECT_NEAR(glm::dot(g.grid.emitted_at(v, h)[c], hemisphere_axis(h)), kPi * emission[c],
                    0.01f * kPi * emission[c]);
      }
    }
  }
  std::printf("furnace grid: expected %.4f %.4f %.4f, on an axis %.4f %.4f %.4f\n", expected.x,
              expected.y, expected.z, axis_value.x, axis_value.y, axis_value.z);
}

// Emitted light in closed form: a black floor (z = 0, 2 km wide) that emits Le upwards only,
// under a sky of radiance Lw. Above the floor every ray either escapes (Lw) or meets the
// floor's emitting side (Le), so I_+z = pi Lw z, I_-z = -pi Le z, and a side hemisphere
// (axis s x) splits into a sky quarter and a floor quarter, each with integral of w = pi / 2
// along the axis and +-pi / 2 along z: I = s pi / 2 (Lw + Le) x + pi / 2 (Lw - Le) z. Nothing
// is reflected (albedo 0), so the bounced vectors stay zero. Without world and emitters the
// grid has no emitted component at all.
// The sky is a constant world, or (second pass) a uniform world image of the same radiance,
// which the escaping rays must read.
TEST(GridGather, EmittedLightFromTheSkyAndAnEmitterIsTheClosedForm) {
  for (const bool image : {false, true}) {
    const glm::vec3 sky(0.5f, 0.25f, 1.0f), floor_emission(1.0f, 2.0f, 3.0f);
    SceneDescription d;
    const uint32_t floor = test::add_material(d, glm::vec3(0.0f), floor_emission, false);
    test::add_quad(d, glm::vec3(0.0f), {1, 0, 0}, {0, 1, 0}, 1000.0f, 1000.0f, floor);
    d.world_radiance = sky;
    if (image) {
      d.world_radiance = glm::vec3(0.0f);
      d.world_texture.texture =
          test::add_texture(d, 16, 8, [](uint32_t, uint32_t) { return glm::vec3(0.25f); });
      d.world_texture.scale = 4.0f * sky;
    }
    SCOPED_TRACE(image ? "world image" : "constant world");
    const GridLayout layout = make_grid_layout({-1, -1, 0.1f}, {1, 1, 0.5f}, {2, 2, 2});
    const GatheredGrid g = gather(d, layout, 1024);
    ASSERT_TRUE(g.grid.has_emitted());
    EXPECT_EQ(g.statistics.invalid_vertices, 0u);
    const float half_pi = 0.5f * kPi;
    float worst = 0.0f;
    for (size_t v = 0; v < g.grid.vertex_count(); ++v) {
      for (int h = 0; h < kGridHemispheres; ++h) {
        const glm::vec3 axis = hemisphere_axis(h);
        for (int c = 0; c < 3; ++c) {
          glm::vec3 expected(0.0f);
          if (h == 4) expected = kPi * sky[c] * axis;
          if (h == 5) expected = kPi * floor_emission[c] * axis;
          if (h < 4) {
            expected = half_pi * (sky[c] + floor_emission[c]) * axis +
                       half_pi * (sky[c] - floor_emission[c]) * glm::vec3(0, 0, 1);
          }
          // 1024 Owen-scrambled Sobol' rays over a piecewise-constant integrand (a jump at the
          // horizon): 0.2% of the larger of sky and floor here; 0.5% (a sky 3% off fails).
          const float tolerance = 0.005f * kPi * std::max(sky[c], floor_emission[c]);
          const glm::vec3 got = g.grid.emitted_at(v, h)[c];
          for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(got[a], expected[a], tolerance)
                << "vertex " << v << " hemisphere " << h << " channel " << c << " axis " << a;
            worst = std::max(worst, std::abs(got[a] - expected[a]) /
                                        (kPi * std::max(sky[c], floor_emission[c])));
          }
          EXPECT_LT(glm::length(g.grid.at(v, h)[c]), 1e-6f);
        }
      }
    }

    std::printf("emitted grid (%s): worst error %.5f of pi max(sky, floor)\n",
                image ? "world image" : "constant world", worst);
  }

  const GridLayout layout = make_grid_layout({-1, -1, 0.1f}, {1, 1, 0.5f}, {2, 2, 2});
  SceneDescription dark;
  test::add_quad(dark, glm::vec3(0.0f), {1, 0, 0}, {0, 1, 0}, 10.0f, 10.0f,
                 test::add_material(dark, glm::vec3(0.5f)));
  dark.lights.push_back(test::point_light({0, 0, 2}, glm::vec3(10.0f)));  // a lamp alone
  EXPECT_FALSE(gather(dark, layout, 4).grid.has_emitted());
}

// A block inside the furnace (same material: the radiance stays uniform): the vertices in it
// see back faces, are marked invalid, and push-pull fills them with their neighbours' light.
TEST(GridGather, VerticesInsideGeometryAreFilled) {
  const float rho = 0.4f;
  const glm::vec3 emission(1.0f);
  SceneDescription d;
  const uint32_t wall = test::add_material(d, glm::vec3(rho), emission, true);
  d.meshes.push_back(inward_sphere(wall));
  d.meshes.push_back(
      test::make_cube(glm::vec3(-0.3f), glm::vec3(0.3f), test::Facing::kOutward, wall));
  const GridLayout layout = make_grid_layout(glm::vec3(-0.8f), glm::vec3(0.8f), {5, 5, 5});
  GatheredGrid g = gather(d, layout, 64);
  // Vertex (2, 2, 2) is the centre, inside the block; the ring around it is outside.
  const size_t centre = layout.vertex_index(2, 2, 2);
  EXPECT_EQ(g.statistics.invalid_vertices, 1u);
  EXPECT_EQ(g.grid.valid[centre], 0);
  EXPECT_EQ(glm::length(g.grid.at(centre, 0)[0]), 0.0f);
  const IrradianceVectorGrid before = g.grid;
  EXPECT_EQ(fill_invalid_vertices(g.grid), 1u);
  const float expected = rho / (1.0f - rho);
  for (int h = 0; h < kGridHemispheres; ++h) {
    EXPECT_NEAR(glm::dot(g.grid.at(centre, h)[1], hemisphere_axis(h)), kPi * expected,
                0.1f * kPi * expected);
  }
  // Valid vertices are never changed.
  for (size_t v = 0; v < g.grid.vertex_count(); ++v) {
    if (!before.valid[v]) continue;
    for (int h = 0; h < kGridHemispheres; ++h) EXPECT_EQ(g.grid.at(v, h), before.at(v, h));
  }
}

// Any method's field: with no light at all, a field that says "indirect value k everywhere"
// makes every wall reflect rho k, and the grid must read rho k along an axis.
class ConstantField : public IndirectField {
 public:
  explicit ConstantField(glm::vec3 value) : value_(value) {}
  void evaluate(const BakePoints& points, std::span<glm::vec3> out, JobContext&) const override {
    for (size_t i = 0; i < points.size(); ++i) out[i] = value_;
  }

 private:
  glm::vec3 value_;
};

TEST(GridGather, OtherMethodsFieldsAreGatheredAtTheHits) {
  const float rho = 0.6f;
  SceneDescription d;
  const uint32_t wall = test::add_material(d, glm::vec3(rho));
  d.meshes.push_back(inward_sphere(wall));
  // A world colour only so that the scene counts as lit: the closed sphere hides it.
  d.world_radiance = glm::vec3(1.0f);
  const ConstantField field(glm::vec3(1.0f, 2.0f, 0.5f));
  const GridLayout layout = make_grid_layout(glm::vec3(-0.5f), glm::vec3(0.5f), {2, 2, 2});
  const GatheredGrid g = gather(d, layout, 128, &field);
  const glm::vec3 value =
      evaluate_grid(g.grid, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, GridInterpolation::kTrilinear);
  for (int c = 0; c < 3; ++c) {
    // Constant radiance: only the stratified directions' cosine sum is noisy (< 1%).
    EXPECT_NEAR(value[c], rho * glm::vec3(1.0f, 2.0f, 0.5f)[c], 0.01f) << c;
  }
}

// A grid whose vectors vary linearly in space is reproduced exactly by trilinear
// interpolation between vertices, and clamped outside.
TEST(GridInterpolation, TrilinearIsExactForLinearFields) {
  const GridLayout layout = make_grid_layout({0, 0, 0}, {4, 4, 4}, {4, 4, 4});
  IrradianceVectorGrid grid(layout);
  auto field_at = [](glm::vec3 p) { return 1.0f + 0.5f * p.x - 0.25f * p.y + 0.125f * p.z; };
  for (uint32_t k = 0; k < 4; ++k)
    for (uint32_t j = 0; j < 4; ++j)
      for (uint32_t i = 0; i < 4; ++i) {
        const size_t v = layout.vertex_index(i, j, k);
        grid.valid[v] = 1;
        const float f = field_at(layout.vertex_position(i, j, k));
        for (int h = 0; h < kGridHemispheres; ++h) {
          grid.at(v, h) = glm::mat3(hemisphere_axis(h) * f, hemisphere_axis(h) * 2.0f * f,
                                    hemisphere_axis(h) * 3.0f * f);
        }
      }
  const glm::vec3 p(1.3f, 2.2f, 0.9f);
  const glm::vec3 on_axis = evaluate_grid(grid, p, {0, -2, 0}, GridInterpolation::kTrilinear);
  EXPECT_NEAR(on_axis.x, field_at(p) / kPi, 1e-5f);
  EXPECT_NEAR(on_axis.z, 3.0f * field_at(p) / kPi, 1e-5f);
  // Outside the outermost vertices (cell centres at 0.5 and 3.5): clamped.
  const glm::vec3 outside =
      evaluate_grid(grid, {-3.0f, 0.5f, 0.5f}, {1, 0, 0}, GridInterpolation::kTrilinear);
  EXPECT_NEAR(outside.x, field_at({0.5f, 0.5f, 0.5f}) / kPi, 1e-5f);
  // The B-spline reproduces linear functions too, away from the clamped border.
  const glm::vec3 cubic =
      evaluate_grid(grid, {2.0f, 2.0f, 2.0f}, {0, 0, 1}, GridInterpolation::kTricubic);
  EXPECT_NEAR(cubic.x, field_at({2.0f, 2.0f, 2.0f}) / kPi, 1e-4f);
  EXPECT_EQ(evaluate_grid(grid, p, {0, 0, 0}, GridInterpolation::kTrilinear), glm::vec3(0.0f));
}

TEST(GridQuantization, Rgb9e5RoundTrip) {
  Pcg32 rng(7, 11);
  for (int i = 0; i < 10000; ++i) {
    const float scale = std::exp2(rng.next_float() * 30.0f - 15.0f);
    const glm::vec3 rgb(rng.next_float() * scale, rng.next_float() * scale,
                        rng.next_float() * scale);
    const glm::vec3 back = decode_rgb9e5(encode_rgb9e5(rgb));
    const float largest = std::max({rgb.x, rgb.y, rgb.z});
    // 9-bit mantissas of the shared exponent: half a step of the largest channel's scale,
    // and no finer than the smallest step, 2^-24.
    const float step = std::max(largest / 511.0f, std::exp2(-24.0f));
    for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(back[c] - rgb[c]), step) << i;
  }
  EXPECT_EQ(decode_rgb9e5(encode_rgb9e5({0, 0, 0})), glm::vec3(0.0f));
  EXPECT_EQ(decode_rgb9e5(encode_rgb9e5({-1.0f, NAN, 1e9f})).y, 0.0f);
  EXPECT_EQ(decode_rgb9e5(encode_rgb9e5({1e9f, 0, 0})).x, kRgb9e5Max);
}

// Quantized hemispheres keep the irradiance along their axis (to R9G9B9E5's precision) and
// their direction to within the 8-bit grid.
TEST(GridQuantization, KeepsTheIrradianceAlongTheAxis) {
  Pcg32 rng(3, 5);
  for (int i = 0; i < 2000; ++i) {
    const int h = int(rng.next_uint() % kGridHemispheres);
    const glm::vec3 axis = hemisphere_axis(h);
    // A hemisphere's vectors: light from directions within it.
    glm::mat3 m(0.0f);
    for (int s = 0; s < 3; ++s) {
      glm::vec3 w(rng.next_float() * 2 - 1, rng.next_float() * 2 - 1, rng.next_float() * 2 - 1);
      w = glm::normalize(w + axis * 1.2f);
      if (glm::dot(w, axis) < 0) w = -w;
      const glm::vec3 colour(rng.next_float(), rng.next_float(), rng.next_float());
      for (int c = 0; c < 3; ++c) m[c] += colour[c] * w;
    }
    const glm::mat3 back = dequantize_hemisphere(quantize_hemisphere(m, h));
    for (int c = 0; c < 3; ++c) {
      const float along = glm::dot(m[c], axis);
      const float largest =
          std::max({glm::dot(m[0], axis), glm::dot(m[1], axis), glm::dot(m[2], axis)});
      EXPECT_NEAR(glm::dot(back[c], axis), along, 2.0f * largest / 511.0f) << i;
    }
  }
}

TEST(GridFile, RoundTripsAndRefusesDamage) {
  const GridLayout layout = make_grid_layout({-1, 0, 2}, {1, 3, 4}, {3, 4, 2});
  IrradianceVectorGrid grid(layout);
  Pcg32 rng(1, 2);
  for (size_t v = 0; v < grid.vertex_count(); ++v) {
    grid.valid[v] = v % 3 != 0;
    for (int h = 0; h < kGridHemispheres; ++h) {
      for (int c = 0; c < 3; ++c) {
        // Physical: light within the hemisphere has a positive component along its axis.
        grid.at(v, h)[c] = hemisphere_axis(h) * (0.2f + rng.next_float()) +
                           glm::vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 0.1f;
      }
    }
  }
  const std::vector<uint8_t> float_bytes =
      encode_grid_file(grid, GridEncoding::kFloat, "{\"a\": 1}");
  const GridFile read = decode_grid_file(float_bytes, "test.bgivg");
  EXPECT_EQ(read.grid.layout.resolution, layout.resolution);
  EXPECT_EQ(read.grid.vectors, grid.vectors);
  EXPECT_EQ(read.grid.valid, grid.valid);
  EXPECT_EQ(read.info_json, "{\"a\": 1}");

  const std::vector<uint8_t> quantized_bytes =
      encode_grid_file(grid, GridEncoding::kQuantized, "{}");
  const GridFile quantized = decode_grid_file(quantized_bytes, "q.bgivg");
  EXPECT_EQ(quantized.encoding, GridEncoding::kQuantized);
  EXPECT_EQ(quantized.grid.vectors, quantized_grid(grid).vectors);
  // 42 bytes a vertex against 216: the paper's 1.3 MB against 3 MB, and better.
  EXPECT_LT(double(quantized_bytes.size()), 0.45 * double(float_bytes.size()));

  // The factorization alone, in floats: exact along each hemisphere's axis.
  const GridFile factored =
      decode_grid_file(encode_grid_file(grid, GridEncoding::kFactored, "{}"), "f.bgivg");
  EXPECT_EQ(factored.encoding, GridEncoding::kFactored);
  for (size_t v = 0; v < grid.vertex_count(); ++v) {
    for (int h = 0; h < kGridHemispheres; ++h) {
      const glm::vec3 axis = hemisphere_axis(h);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(glm::dot(factored.grid.at(v, h)[c], axis), glm::dot(grid.at(v, h)[c], axis),
                    1e-5f);
      }
    }
  }

  // Version 1 without emitted light (what readers of before and the web page read); version
  // 2 carries it, in any encoding.
  const auto version_of = [](const std::vector<uint8_t>& bytes) {
    return uint32_t(bytes[8]) | uint32_t(bytes[9]) << 8;
  };
  EXPECT_EQ(version_of(float_bytes), 1u);
  EXPECT_FALSE(read.grid.has_emitted());
  IrradianceVectorGrid with_emitted = grid;
  with_emitted.emitted = grid.vectors;
  for (glm::mat3& m : with_emitted.emitted) m *= 0.5f;
  const std::vector<uint8_t> emitted_bytes =
      encode_grid_file(with_emitted, GridEncoding::kFloat, "{}");
  EXPECT_EQ(version_of(emitted_bytes), 2u);
  const GridFile emitted_read = decode_grid_file(emitted_bytes, "e.bgivg");
  EXPECT_EQ(emitted_read.grid.vectors, grid.vectors);
  EXPECT_EQ(emitted_read.grid.emitted, with_emitted.emitted);
  const GridFile emitted_quantized =
      decode_grid_file(encode_grid_file(with_emitted, GridEncoding::kQuantized, "{}"), "eq.bgivg");
  IrradianceVectorGrid emitted_alone = grid;
  emitted_alone.vectors = with_emitted.emitted;
  EXPECT_EQ(emitted_quantized.grid.emitted, quantized_grid(emitted_alone).vectors);
  EXPECT_THROW(decode_grid_file(std::span(emitted_bytes).first(emitted_bytes.size() - 9), "t"),
               Error);

  std::vector<uint8_t> damaged = float_bytes;
  damaged[damaged.size() / 2] ^= 0x40;
  EXPECT_THROW(decode_grid_file(damaged, "damaged.bgivg"), Error);
  EXPECT_THROW(decode_grid_file(std::span(float_bytes).first(float_bytes.size() - 9), "t"), Error);
}

}  // namespace
}  // namespace bakegi
