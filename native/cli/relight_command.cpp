// bakegi relight scene.bgs [--move x,y,z] [--scale k] [--repeat R] [--check] --out values.npy
//                          [settings]
// Times relighting without relinking: bakes the scene once, moves every light by (x, y, z)
// metres and scales its power by k, then relights from the first bake's precomputation
// (bakegi_job_start_relight), keeping the fastest of R relights. --check also bakes the
// changed scene from scratch and reports the error of the relight against it (0 when
// relighting is exactly a full bake with the new lights, as it should be). Prints one JSON
// object: seconds of the full bake, of the relight (wall, and the core's solve), the check.
#include <cmath>
#include <cstdio>
#include <string>

#include "arguments.h"
#include "bake_run.h"
#include "bake_settings.h"
#include "commands.h"
#include "exit_codes.h"
#include "json_value.h"
#include "npy_file.h"
#include "scene_file.h"
#include "usage_error.h"
#include "error_metric.h"

namespace bakegi::cli {

namespace {

double parse_number(const std::string& text, const std::string& what) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value)) {
    throw UsageError(what + " must be a finite number, not '" + text + "'");
  }
  return value;
}

// "x,y,z" → three numbers.
void parse_vector(const std::string& text, float out[3]) {
  size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const size_t comma = text.find(',', start);
    if ((i < 2) != (comma != std::string::npos)) {
      throw UsageError("--move expects x,y,z, not '" + text + "'");
    }
    out[i] = float(parse_number(text.substr(start, comma - start), "--move"));
    start = comma + 1;
  }
}

// Moves every light of `scene` by `offset` and scales its color by `scale`.
void change_lights(bakegi_scene* scene, const float offset[3], float scale) {
  const uint32_t count = bakegi_scene_light_count(scene);
  std::vector<bakegi_light_desc> lights(count);
  for (uint32_t i = 0; i < count; ++i) {
    check(bakegi_scene_get_light(scene, i, &lights[i]), "reading light " + std::to_string(i));
  }
  check(bakegi_scene_clear_lights(scene), "clearing the lights");
  for (bakegi_light_desc& light : lights) {
    for (int c = 0; c < 3; ++c) {
      light.position[c] += offset[c];
      light.color[c] *= scale;
    }
    check(bakegi_scene_add_light(scene, &light, nullptr), "adding a changed light");
  }
}

// The core's seconds for `stage` in a report (0 when absent).
double stage_seconds(const std::string& report, const std::string& stage) {
  const JsonValue json = JsonValue::parse(report);
  const JsonValue* value = json.find_path({"seconds", stage});
  return value ? value->number().value_or(0.0) : 0.0;
}

}  // namespace

int run_relight_command(const std::vector<std::string>& words) {
  std::vector<OptionSpec> specs = bake_setting_options();
  specs.push_back({"out"});
  specs.push_back({"move"});
  specs.push_back({"scale"});
  specs.push_back({"repeat"});
  specs.push_back({"check", false});
  const Arguments args(words, specs);
  if (args.positional().size() != 1) throw UsageError("relight expects one scene file");
  const std::string out_path = args.require("out");
  check_output_folder(out_path);
  const BakeSettings settings = bake_settings_from(args);
  float offset[3] = {0.0f, 0.0f, 0.0f};
  if (const auto move = args.value("move")) parse_vector(*move, offset);
  const double scale = args.value("scale") ? parse_number(*args.value("scale"), "--scale") : 1.0;
  if (!(scale >= 0.0)) throw UsageError("--scale must not be negative");
  const int64_t repeat = args.int_value("repeat", 1, 1, 1000);

  const SceneFile file = load_scene_file_with_points(args.positional()[0]);
  const uint64_t count = bakegi_points_count(file.points.get());
  const BakeRun full = run_bake(file.scene.get(), file.points.get(), settings, "full bake");
  if (!bakegi_job_can_relight(full.job.get())) {
    throw UsageError("method '" + settings.method() +
                     "' cannot relight (antiradiance and meshless can)");
  }

  change_lights(file.scene.get(), offset, float(scale));
  BakeRun best;
  for (int64_t r = 0; r < repeat; ++r) {
    BakeRun run = run_relight(full.job.get(), file.scene.get(), count, nullptr, "relight");
    if (r == 0 || run.wall_seconds < best.wall_seconds) best = std::move(run);
  }
  write_npy_float32(out_path, best.values.data(), {count, 3});

  std::string check_json = "null";
  if (args.has("check")) {
    const BakeRun fresh = run_bake(file.scene.get(), file.points.get(), settings, "check bake");
    const auto error = relative_rmse_luminance(best.values.data(), fresh.values.data(), count);
    char text[160];
    std::snprintf(text, sizeof text, "{\"full_bake_seconds\": %.6f, \"error\": %.9g}",
                  fresh.wall_seconds, error ? *error : -1.0);
    check_json = text;
  }
  std::printf(
      "{\"points\": %llu, \"full_seconds\": %.6f, \"full_solve_seconds\": %.6f, "
      "\"relight_seconds\": %.6f, \"relight_solve_seconds\": %.6f, \"repeat\": %lld, "
      "\"check\": %s}\n",
      static_cast<unsigned long long>(count), full.wall_seconds,
      stage_seconds(full.report_json, "solve"), best.wall_seconds,
      stage_seconds(best.report_json, "solve"), static_cast<long long>(repeat), check_json.c_str());
  return kExitOk;
}

}  // namespace bakegi::cli
