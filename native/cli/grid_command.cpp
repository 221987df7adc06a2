// bakegi grid bake|apply|info: Irradiance Vector Grids from the command line (docs/ivg.md).
//   grid bake scene.bgs --out grid.bgivg [--cell S] [--max-vertices N] [--rays R]
//             [--bounds x0,y0,z0,x1,y1,z1] [--quantized] [--report r.json] [settings]
//   grid apply grid.bgivg scene.bgs --out values.npy [--tricubic] [--absolute] [--repeat R]
//              [--with-emitted]
//   grid info grid.bgivg
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "arguments.h"
#include "bake_run.h"
#include "commands.h"
#include "exit_codes.h"
#include "file_error.h"
#include "npy_file.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

namespace {

GridHandle read_grid(const std::string& path) {
  bakegi_grid* raw = nullptr;
  check(bakegi_grid_read_file(path.c_str(), &raw), "reading " + path);
  return GridHandle(raw);
}

std::string grid_info_json(const bakegi_grid* grid) {
  size_t length = 0;
  check(bakegi_grid_get_info_json(grid, nullptr, 0, &length), "reading the grid's info");
  std::string json(length + 1, '\0');
  check(bakegi_grid_get_info_json(grid, json.data(), json.size(), &length),
        "reading the grid's info");
  json.resize(length);
  return json;
}

int run_grid_bake(const std::vector<std::string>& words) {
  std::vector<OptionSpec> specs = bake_setting_options();
  for (const char* name : {"out", "cell", "max-vertices", "rays", "bounds", "report"}) {
    specs.push_back({name});
  }
  specs.push_back({"quantized", false});
  const Arguments args(words, specs);
  if (args.positional().size() != 1) throw UsageError("grid bake expects one scene file");
  const std::string out_path = args.require("out");
  check_output_folder(out_path);
  const float cell = args.value("cell") ? parse_float(*args.value("cell"), "--cell") : 0.0f;
  const int64_t max_vertices = args.int_value("max-vertices", 0, 0, int64_t(1) << 30);
  const int64_t rays = args.int_value("rays", 0, 0, 65536);
  const BakeSettings settings = bake_settings_from(args);

  const SceneFile file = load_scene_file(args.positional()[0]);
  float lo[3], hi[3];
  if (const auto bounds = args.value("bounds")) {
    const std::vector<float> b = parse_float_list(*bounds, "--bounds (x0,y0,z0,x1,y1,z1)", 6);
    std::copy(b.begin(), b.begin() + 3, lo);
    std::copy(b.begin() + 3, b.end(), hi);
  } else {
    check(bakegi_scene_get_bounds(file.scene.get(), lo, hi), "the scene's bounds");
  }
  bakegi_grid* raw_layout = nullptr;
  check(bakegi_grid_create(lo, hi, cell, uint64_t(max_vertices), &raw_layout), "the grid layout");
  const GridHandle layout(raw_layout);
  const SettingsHandle core_settings = settings.to_core();
  BakeRun run = run_job(
      [&](bakegi_job** out) {
        return bakegi_job_start_grid(file.scene.get(), layout.get(), uint32_t(rays),
                                     core_settings.get(), out);
      },
      0, "grid " + settings.method());
  bakegi_grid* raw_grid = nullptr;
  check(bakegi_job_get_grid(run.job.get(), &raw_grid), "reading the grid");
  const GridHandle grid(raw_grid);
  const std::string info = "{\"method\": \"" + settings.method() +
                           "\", \"settings\": " + settings.to_json() +
                           ", \"seconds\": " + std::to_string(run.wall_seconds) + "}";
  check(bakegi_grid_write_file(grid.get(), out_path.c_str(),
                               args.has("quantized") ? BAKEGI_GRID_QUANTIZED : BAKEGI_GRID_FLOAT,
                               info.c_str()),
        "writing " + out_path);
  if (const auto report_path = args.value("report")) {
    write_output_file(*report_path, run.report_json + "\n");
  }
  bakegi_grid_info grid_info{};
  check(bakegi_grid_get_info(grid.get(), &grid_info), "the grid's info");
  std::printf("%s\n", run.report_json.c_str());
  std::fprintf(
      stderr, "baked a %ux%ux%u grid (%llu of %llu vertices inside geometry) in %.3f s -> %s\n",
      grid_info.resolution[0], grid_info.resolution[1], grid_info.resolution[2],
      static_cast<unsigned long long>(grid_info.invalid_vertices),
      static_cast<unsigned long long>(grid_info.vertex_count), run.wall_seconds, out_path.c_str());
  return kExitOk;
}

int run_grid_apply(const std::vector<std::string>& words) {
  const Arguments args(
      words,
      {{"out"}, {"tricubic", false}, {"absolute", false}, {"repeat"}, {"with-emitted", false}});
  if (args.positional().size() != 2) throw UsageError("grid apply expects a grid and a scene file");
  const std::string out_path = args.require("out");
  check_output_folder(out_path);
  const int64_t repeat = args.int_value("repeat", 1, 1, 1000);
  GridHandle grid = read_grid(args.positional()[0]);
  if (args.has("with-emitted")) {
    // What the web page draws besides its lamps: the bounced light plus the world's and
    // emitters' direct light the grid carries.
    bakegi_grid* page = nullptr;
    check(bakegi_grid_with_emitted_light(grid.get(), &page, nullptr), "adding the emitted light");
    grid = GridHandle(page);
  }
  const SceneFile file = load_scene_file_with_points(args.positional()[1]);
  const uint64_t count = bakegi_points_count(file.points.get());
  std::vector<float> positions(3 * count), normals(3 * count), values(3 * count);
  check(bakegi_points_get(file.points.get(), positions.data(), normals.data(), nullptr),
        "reading the bake points");
  const int interpolation = args.has("tricubic") ? BAKEGI_GRID_TRICUBIC : BAKEGI_GRID_TRILINEAR;
  const int directional = args.has("absolute") ? BAKEGI_GRID_ABSOLUTE : BAKEGI_GRID_SQUARED;
  double fastest = std::numeric_limits<double>::infinity();
  for (int64_t r = 0; r < repeat; ++r) {
    const auto start = std::chrono::steady_clock::now();
    check(bakegi_grid_evaluate(grid.get(), positions.data(), normals.data(), count, interpolation,
                               directional, values.data()),
          "evaluating the grid");
    fastest = std::min(
        fastest, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  write_npy_float32(out_path, values.data(), {count, 3});
  std::printf(
      "{\"points\": %llu, \"seconds\": %.6f, \"interpolation\": \"%s\", \"directional\": "
      "\"%s\"}\n",
      static_cast<unsigned long long>(count), fastest,
      interpolation == BAKEGI_GRID_TRICUBIC ? "tricubic" : "trilinear",
      directional == BAKEGI_GRID_ABSOLUTE ? "absolute" : "squared");
  return kExitOk;
}

int run_grid_info(const std::vector<std::string>& words) {
  const Arguments args(words, {});
  if (args.positional().size() != 1) throw UsageError("grid info expects one grid file");
  const GridHandle grid = read_grid(args.positional()[0]);
  bakegi_grid_info info{};
  check(bakegi_grid_get_info(grid.get(), &info), "the grid's info");
  std::printf("bounds:     (%g, %g, %g) to (%g, %g, %g)\n", info.bounds_min[0], info.bounds_min[1],
              info.bounds_min[2], info.bounds_max[0], info.bounds_max[1], info.bounds_max[2]);
  std::printf("resolution: %u x %u x %u (%llu vertices)\n", info.resolution[0], info.resolution[1],
              info.resolution[2], static_cast<unsigned long long>(info.vertex_count));
  std::printf("inside:     %llu vertices inside geometry (filled from their neighbours)\n",
              static_cast<unsigned long long>(info.invalid_vertices));
  int has_emitted = 0;
  check(bakegi_grid_with_emitted_light(grid.get(), nullptr, &has_emitted), "the grid's components");
  std::printf("emitted:    %s\n", has_emitted ? "the world's and emitters' direct light, kept apart"
                                              : "none (no world or emitters, or an older grid)");
  std::printf("made by:    %s\n", grid_info_json(grid.get()).c_str());
  return kExitOk;
}

}  // namespace

int run_grid_command(const std::vector<std::string>& words) {
  if (words.empty()) throw UsageError("grid expects bake, apply or info");
  const std::vector<std::string> rest(words.begin() + 1, words.end());
  if (words[0] == "bake") return run_grid_bake(rest);
  if (words[0] == "apply") return run_grid_apply(rest);
  if (words[0] == "info") return run_grid_info(rest);
  throw UsageError("unknown grid command '" + words[0] + "' (bake, apply or info)");
}

}  // namespace bakegi::cli
