// bakegi bake scene.bgs [--method M] [--samples N] [--seed S] [--sample-offset K]
//                       [--threads T] [--set key=value ...] [--out values.npy]
//                       [--report report.json]
//                       [--lightmaps layout.bgl --exr-dir DIR [--padding N] [--float]
//                        [--compression zip|piz|none]]
// At least one of --out and --exr-dir.
#include <cstdio>
#include <optional>

#include "arguments.h"
#include "bake_run.h"
#include "commands.h"
#include "exit_codes.h"
#include "file_error.h"
#include "lightmap_output.h"
#include "npy_file.h"
#include "report_summary.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

int run_bake_command(const std::vector<std::string>& words) {
  std::vector<OptionSpec> specs = bake_setting_options();
  specs.push_back({"out"});
  specs.push_back({"report"});
  for (const OptionSpec& spec : lightmap_output_options()) specs.push_back(spec);
  const Arguments args(words, specs);
  if (args.positional().size() != 1) throw UsageError("bake expects one scene file");
  const std::string scene_path = args.positional()[0];
  const std::optional<LightmapOutput> lightmap_output = lightmap_output_from(args);
  const std::optional<std::string> out_path = args.value("out");
  if (!out_path && !lightmap_output) {
    throw UsageError("bake needs --out values.npy and/or --lightmaps layout.bgl --exr-dir DIR");
  }
  const BakeSettings settings = bake_settings_from(args);
  if (out_path) check_output_folder(*out_path);
  if (const auto report_path = args.value("report")) check_output_folder(*report_path);

  const SceneFile file = load_scene_file_with_points(scene_path);
  const uint64_t count = bakegi_points_count(file.points.get());
  // Before the bake: a layout that does not match the points fails now, not after it.
  LightmapsHandle lightmaps;
  if (lightmap_output) {
    lightmaps = prepare_lightmap_output(*lightmap_output, scene_path, file.points.get());
  }
  const BakeRun run = run_bake(file.scene.get(), file.points.get(), settings, settings.method());

  if (out_path) write_npy_float32(*out_path, run.values.data(), {count, 3});
  if (const auto report_path = args.value("report")) {
    write_output_file(*report_path, run.report_json + "\n");
  }
  std::printf("%s\n", run.report_json.c_str());
  std::fprintf(stderr, "baked %llu points with %s in %.3f s%s%s\n",
               static_cast<unsigned long long>(count), settings.method().c_str(), run.wall_seconds,
               out_path ? " -> " : "", out_path ? out_path->c_str() : "");
  const std::string estimate = describe_estimated_error(summarize_report(run.report_json));
  if (!estimate.empty()) std::fprintf(stderr, "%s\n", estimate.c_str());
  if (lightmap_output) write_lightmap_exrs(lightmaps.get(), *lightmap_output, run.values);
  return kExitOk;
}

std::vector<float> load_rgb_array(const std::string& path, uint64_t expected_points) {
  NpyArray array = read_npy_float32(path);
  if (array.shape.size() != 2 || array.shape[1] != 3 || array.shape[0] != expected_points) {
    std::string shape;
    for (const auto s : array.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(s);
    throw FileError(path + ": shape is (" + shape + "), expected (" +
                    std::to_string(expected_points) + ", 3)");
  }
  return std::move(array.data);
}

}  // namespace bakegi::cli
