// The grid through the C API (bakegi_grid_*, bakegi_job_start_grid,
// bakegi_points_flag_inside): a grid job agrees with a bake at the same points, files round
// trip, bad input is refused with a message, and buried points are flagged.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "capi_test_scene.h"

namespace bakegi {
namespace {

using test::new_box_scene;
using test::new_floor_points;
using test::new_settings;

GridHandle grid_layout(float lo, float hi, float cell) {
  const float bounds_min[3] = {lo, lo, lo}, bounds_max[3] = {hi, hi, hi};
  bakegi_grid* grid = nullptr;
  EXPECT_EQ(bakegi_grid_create(bounds_min, bounds_max, cell, 0, &grid), BAKEGI_OK)
      << bakegi_last_error();
  return GridHandle(grid);
}

std::vector<float> bake_points(const bakegi_scene* scene, const bakegi_points* points,
                               int64_t samples) {
  const auto settings = new_settings();
  EXPECT_EQ(bakegi_settings_set_int(settings.get(), "samples", samples), BAKEGI_OK);
  bakegi_job* raw = nullptr;
  EXPECT_EQ(bakegi_job_start(scene, points, settings.get(), &raw), BAKEGI_OK);
  const JobHandle job(raw);
  EXPECT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << bakegi_last_error();
  std::vector<float> out(3 * bakegi_points_count(points));
  EXPECT_EQ(bakegi_job_get_result(job.get(), out.data(), bakegi_points_count(points)), BAKEGI_OK);
  return out;
}

// The unit box lit from its centre: the grid's light on the floor against the path tracer's.
TEST(GridApi, GridJobAgreesWithABakeAtTheSamePoints) {
  const auto scene = new_box_scene();
  const GridHandle layout = grid_layout(0.0f, 1.0f, 0.25f);
  bakegi_grid_info info{};
  ASSERT_EQ(bakegi_grid_get_info(layout.get(), &info), BAKEGI_OK);
  EXPECT_EQ(info.resolution[0], 4u);
  EXPECT_EQ(info.vertex_count, 64u);

  const auto settings = new_settings();
  bakegi_job* raw = nullptr;
  ASSERT_EQ(bakegi_job_start_grid(scene.get(), layout.get(), 128, settings.get(), &raw), BAKEGI_OK)
      << bakegi_last_error();
  const JobHandle job(raw);
  ASSERT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << bakegi_last_error();
  bakegi_grid* baked_raw = nullptr;
  ASSERT_EQ(bakegi_job_get_grid(job.get(), &baked_raw), BAKEGI_OK);
  const GridHandle baked(baked_raw);

  const auto points = new_floor_points(16);
  std::vector<float> positions(48), normals(48), from_grid(48);
  ASSERT_EQ(bakegi_points_get(points.get(), positions.data(), normals.data(), nullptr), BAKEGI_OK);
  ASSERT_EQ(bakegi_grid_evaluate(baked.get(), positions.data(), normals.data(), 16,
                                 BAKEGI_GRID_TRILINEAR, BAKEGI_GRID_SQUARED, from_grid.data()),
            BAKEGI_OK);
  const std::vector<float> baked_values = bake_points(scene.get(), points.get(), 512);
  double grid_sum = 0.0, bake_sum = 0.0;
  for (size_t i = 0; i < 48; ++i) {
    grid_sum += from_grid[i];
    bake_sum += baked_values[i];
  }
  // The floor's mean indirect light: a 4^3 grid (cells of 25 cm in a 1 m room) holds it to
  // a few percent; 10% bound (the grid and the bake each carry about 1% noise).
  EXPECT_NEAR(grid_sum / bake_sum, 1.0, 0.10) << grid_sum << " " << bake_sum;

  // A grid bake has no points: get_result refuses nothing but has nothing to give, a plain
  // job has no grid.
  bakegi_grid* none = nullptr;
  const auto plain_points = new_floor_points(1);
  bakegi_job* plain_raw = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), plain_points.get(), settings.get(), &plain_raw),
            BAKEGI_OK);
  const JobHandle plain(plain_raw);
  ASSERT_EQ(bakegi_job_wait(plain.get()), BAKEGI_OK);
  EXPECT_EQ(bakegi_job_get_grid(plain.get(), &none), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(none, nullptr);
}

// The report's "estimated_error" of a grid job (a number in the JSON).
double estimated_error(const bakegi_job* job) {
  size_t length = 0;
  EXPECT_EQ(bakegi_job_get_report(job, nullptr, 0, &length), BAKEGI_OK);
  std::string report(length + 1, '\0');
  EXPECT_EQ(bakegi_job_get_report(job, report.data(), report.size(), &length), BAKEGI_OK);
  const size_t at = report.find("\"estimated_error\": ");
  EXPECT_NE(at, std::string::npos) << report;
  return at == std::string::npos ? -1.0 : std::stod(report.substr(at + 19));
}

double grid_job_estimate(float cell, uint32_t rays) {
  const auto scene = new_box_scene();
  const GridHandle layout = grid_layout(0.0f, 1.0f, cell);
  const auto settings = new_settings();
  bakegi_job* raw = nullptr;
  EXPECT_EQ(bakegi_job_start_grid(scene.get(), layout.get(), rays, settings.get(), &raw),
            BAKEGI_OK);
  const JobHandle job(raw);
  EXPECT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << bakegi_last_error();
  return estimated_error(job.get());
}

// A grid bake checks itself against the path tracer at probes on the surfaces in its box: a
// 4^3 grid of 128 rays a hemisphere estimates a small error in the lit box, a 2^3 grid of one
// ray a hemisphere (noise of the order of the light itself) a much larger one.
TEST(GridApi, AGridEstimatesItsOwnError) {
  const double good = grid_job_estimate(0.25f, 128);
  const double poor = grid_job_estimate(0.5f, 1);
  std::printf("grid estimated error: 4^3 x 128 rays %.4f, 2^3 x 1 ray %.4f\n", good, poor);
  EXPECT_GE(good, 0.0);
  EXPECT_LT(good, 0.15);
  EXPECT_GT(poor, 2.0 * good);
}

TEST(GridApi, FilesRoundTripAndBadInputIsRefused) {
  const GridHandle layout = grid_layout(-1.0f, 1.0f, 0.5f);
  const auto path = std::filesystem::temp_directory_path() / "bakegi_grid_api_test.bgivg";
  for (int encoding : {BAKEGI_GRID_FLOAT, BAKEGI_GRID_QUANTIZED, BAKEGI_GRID_FACTORED}) {
    ASSERT_EQ(bakegi_grid_write_file(layout.get(), path.c_str(), encoding, "{\"made\": \"here\"}"),
              BAKEGI_OK);
    bakegi_grid* raw = nullptr;
    ASSERT_EQ(bakegi_grid_read_file(path.c_str(), &raw), BAKEGI_OK) << bakegi_last_error();
    const GridHandle read(raw);
    bakegi_grid_info info{};
    ASSERT_EQ(bakegi_grid_get_info(read.get(), &info), BAKEGI_OK);
    EXPECT_EQ(info.resolution[2], 4u);
    char json[64];
    size_t length = 0;
    ASSERT_EQ(bakegi_grid_get_info_json(read.get(), json, sizeof json, &length), BAKEGI_OK);
    EXPECT_STREQ(json, "{\"made\": \"here\"}");
  }
  EXPECT_EQ(bakegi_grid_write_file(layout.get(), path.c_str(), 7, nullptr),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  {  // not a grid file
    std::ofstream(path, std::ios::binary | std::ios::trunc) << "BAKEGI\0S garbage";
  }
  bakegi_grid* raw = nullptr;
  EXPECT_EQ(bakegi_grid_read_file(path.c_str(), &raw), BAKEGI_ERROR_BAD_FILE);
  EXPECT_EQ(raw, nullptr);
  std::filesystem::remove(path);
  EXPECT_EQ(bakegi_grid_read_file(path.c_str(), &raw), BAKEGI_ERROR_IO);

  const float lo[3] = {0, 0, 0}, inverted[3] = {-1, 1, 1}, nan[3] = {0, NAN, 1};
  EXPECT_EQ(bakegi_grid_create(lo, inverted, 0.1f, 0, &raw), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(test::last_error().find("inverted"), std::string::npos) << test::last_error();
  EXPECT_EQ(bakegi_grid_create(lo, nan, 0.1f, 0, &raw), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_grid_create(nullptr, lo, 0.1f, 0, &raw), BAKEGI_ERROR_INVALID_ARGUMENT);
  const float one[3] = {0, 0, 1};
  float out[3];
  EXPECT_EQ(bakegi_grid_evaluate(layout.get(), one, one, 1, 5, 0, out),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_grid_evaluate(layout.get(), one, one, 1, 0, 9, out),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_grid_evaluate(nullptr, one, one, 1, 0, 0, out), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_grid_evaluate(layout.get(), one, one, 0, 0, 0, nullptr), BAKEGI_OK);
  const auto scene = new_box_scene();
  const auto settings = new_settings();
  bakegi_job* job = nullptr;
  EXPECT_EQ(bakegi_job_start_grid(scene.get(), layout.get(), 70000, settings.get(), &job),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_job_start_grid(scene.get(), nullptr, 8, settings.get(), &job),
            BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(job, nullptr);
}

// A block standing on the box's floor: the floor under it is buried (its rays meet the
// block's inside), the floor beside it is not.
TEST(GridApi, PointsUnderABlockAreFlaggedInside) {
  const auto scene = new_box_scene();
  const std::vector<float> block = {0.4f, 0.4f, 0.0f, 0.6f, 0.4f, 0.0f, 0.6f, 0.6f,
                                    0.0f, 0.4f, 0.6f, 0.0f, 0.4f, 0.4f, 0.2f, 0.6f,
                                    0.4f, 0.2f, 0.6f, 0.6f, 0.2f, 0.4f, 0.6f, 0.2f};
  // The inward box's faces, reversed: normals point out of the block.
  const test::BoxMesh inward;
  std::vector<uint32_t> outward = inward.indices;
  for (size_t t = 0; t < outward.size(); t += 3) std::swap(outward[t + 1], outward[t + 2]);
  bakegi_mesh_desc mesh{};
  mesh.positions = block.data();
  mesh.vertex_count = 8;
  mesh.indices = outward.data();
  mesh.triangle_count = uint32_t(outward.size() / 3);
  ASSERT_EQ(bakegi_scene_add_mesh(scene.get(), &mesh, nullptr), BAKEGI_OK);
  const float positions[6] = {0.5f, 0.5f, 0.001f, 0.2f, 0.2f, 0.001f};
  const float normals[6] = {0, 0, 1, 0, 0, 1};
  bakegi_points* raw = nullptr;
  ASSERT_EQ(bakegi_points_create(positions, normals, nullptr, 2, &raw), BAKEGI_OK);
  const PointsHandle points(raw);
  uint8_t flags[2] = {7, 7};
  ASSERT_EQ(bakegi_points_flag_inside(points.get(), scene.get(), 0, 0.0f, 0.0f, flags), BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_EQ(flags[0], 1);
  EXPECT_EQ(flags[1], 0);
  EXPECT_EQ(bakegi_points_flag_inside(points.get(), scene.get(), 0, 2.0f, 0.0f, flags),
            BAKEGI_ERROR_INVALID_ARGUMENT);
}

// Method "grid": a bake at the points reads the grid file as Apply Grid does
// (bakegi_grid_evaluate_in_scene with visibility and buried points, |n| weights), and a bake
// without a file, or with a missing one, is refused with a message.
TEST(GridApi, MethodGridBakesThePointsFromAGridFile) {
  const auto scene = new_box_scene();
  const GridHandle layout = grid_layout(0.0f, 1.0f, 0.25f);
  const auto grid_settings = new_settings();
  bakegi_job* raw = nullptr;
  ASSERT_EQ(bakegi_job_start_grid(scene.get(), layout.get(), 32, grid_settings.get(), &raw),
            BAKEGI_OK);
  const JobHandle grid_job(raw);
  ASSERT_EQ(bakegi_job_wait(grid_job.get()), BAKEGI_OK) << bakegi_last_error();
  bakegi_grid* baked_raw = nullptr;
  ASSERT_EQ(bakegi_job_get_grid(grid_job.get(), &baked_raw), BAKEGI_OK);
  const GridHandle baked(baked_raw);
  const std::string path =
      (std::filesystem::temp_directory_path() / "bakegi_method_grid_test.bgivg").string();
  ASSERT_EQ(bakegi_grid_write_file(baked.get(), path.c_str(), BAKEGI_GRID_FLOAT, nullptr),
            BAKEGI_OK);

  const auto points = new_floor_points(25);
  std::vector<float> positions(75), normals(75), expected(75);
  ASSERT_EQ(bakegi_points_get(points.get(), positions.data(), normals.data(), nullptr), BAKEGI_OK);
  ASSERT_EQ(bakegi_grid_evaluate_in_scene(
                baked.get(), scene.get(), positions.data(), normals.data(), 25,
                BAKEGI_GRID_TRILINEAR, BAKEGI_GRID_ABSOLUTE,
                BAKEGI_GRID_VISIBILITY | BAKEGI_GRID_DARKEN_BURIED, expected.data(), nullptr),
            BAKEGI_OK);

  const auto settings = new_settings();
  ASSERT_EQ(bakegi_settings_set_string(settings.get(), "method", "grid"), BAKEGI_OK);
  bakegi_job* refused_raw = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &refused_raw), BAKEGI_OK);
  const JobHandle refused(refused_raw);
  EXPECT_EQ(bakegi_job_wait(refused.get()), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(bakegi_last_error()).find("grid_file"), std::string::npos)
      << bakegi_last_error();
  ASSERT_EQ(bakegi_settings_set_string(settings.get(), "grid_file", path.c_str()), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "error_probes", 0), BAKEGI_OK);
  bakegi_job* job_raw = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &job_raw), BAKEGI_OK)
      << bakegi_last_error();
  const JobHandle job(job_raw);
  ASSERT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << bakegi_last_error();
  std::vector<float> out(75);
  ASSERT_EQ(bakegi_job_get_result(job.get(), out.data(), 25), BAKEGI_OK);
  for (size_t i = 0; i < out.size(); ++i) EXPECT_FLOAT_EQ(out[i], expected[i]) << i;
  EXPECT_GT(expected[1], 0.0f);

  std::remove(path.c_str());
  // The file is read when the job solves, in its thread: the job fails, naming it.
  bakegi_job* missing_raw = nullptr;
  ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &missing_raw), BAKEGI_OK);
  const JobHandle missing(missing_raw);
  EXPECT_EQ(bakegi_job_wait(missing.get()), BAKEGI_ERROR_IO);
  EXPECT_NE(std::string(bakegi_last_error()).find("bakegi_method_grid_test"), std::string::npos)
      << bakegi_last_error();
}

}  // namespace
}  // namespace bakegi
