// bakegi sweep scene.bgs --method M --samples 1,2,4,... --reference ref.npy --out sweep.json
//                        [--seed S] [--threads T] [--repeat R] [--set key=value ...]
// Bakes at each quality setting, times each bake and measures its error against the
// reference (native/common/error_metric.h). With --repeat R each setting is baked R times and the
// fastest wall time is kept (the machine is shared; the minimum is the least disturbed).
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <thread>

#include "arguments.h"
#include "bake_run.h"
#include "commands.h"
#include "error_metric.h"
#include "exit_codes.h"
#include "file_error.h"
#include "json_value.h"
#include "npy_file.h"
#include "report_summary.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {
namespace {

std::string optional_number(const std::optional<double>& v) {
  return v ? json_number(*v) : "null";
}

}  // namespace

int run_sweep_command(const std::vector<std::string>& words) {
  std::vector<OptionSpec> specs = bake_setting_options();
  specs.push_back({"reference"});
  specs.push_back({"out"});
  specs.push_back({"repeat"});
  const Arguments args(words, specs);
  if (args.positional().size() != 1) throw UsageError("sweep expects one scene file");
  const std::string scene_path = args.positional()[0];
  const std::string reference_path = args.require("reference");
  const std::string out_path = args.require("out");
  const std::vector<int64_t> sample_counts =
      parse_int_list(args.require("samples"), "--samples", 1, INT32_MAX);
  const int64_t repeat = args.int_value("repeat", 1, 1, 100);
  const BakeSettings base = bake_settings_from(args, {"samples"});
  check_output_folder(out_path);

  const SceneFile file = load_scene_file_with_points(scene_path);
  const uint64_t count = bakegi_points_count(file.points.get());
  const std::vector<float> reference = load_rgb_array(reference_path, count);

  std::string runs_json;
  std::printf("%-10s %8s %10s %12s %12s %14s\n", "method", "samples", "seconds", "error", "rays",
              "memory_bytes");
  for (const int64_t samples : sample_counts) {
    BakeSettings settings = base;
    settings.set("samples", samples);
    const std::string label = settings.method() + " " + std::to_string(samples) + " spp";

    BakeRun best;
    std::vector<double> all_seconds;
    for (int64_t r = 0; r < repeat; ++r) {
      BakeRun run = run_bake(file.scene.get(), file.points.get(), settings, label);
      all_seconds.push_back(run.wall_seconds);
      if (r == 0 || run.wall_seconds < best.wall_seconds) best = std::move(run);
    }
    const auto metrics = error_metrics(best.values.data(), reference.data(), count);
    const auto metric = [&](double ErrorMetrics::* field) {
      return metrics ? std::optional<double>((*metrics).*field) : std::nullopt;
    };
    const std::optional<double> error = metric(&ErrorMetrics::relative_rmse);
    const ReportSummary summary = summarize_report(best.report_json);

    std::string seconds_list;
    for (const double s : all_seconds)
      seconds_list += (seconds_list.empty() ? "" : ", ") + json_number(s);
    runs_json += std::string(runs_json.empty() ? "" : ",\n") +
                 "    {\"method\": " + json_quote(settings.method()) +
                 ", \"settings\": " + settings.to_json() +
                 ", \"seconds\": " + json_number(best.wall_seconds) + ", \"seconds_all\": [" +
                 seconds_list + "], \"core_seconds\": " + optional_number(summary.core_seconds) +
                 ", \"error\": " + optional_number(error) +
                 ", \"nrmse\": " + optional_number(metric(&ErrorMetrics::nrmse)) +
                 ", \"weighted_relative_rmse\": " +
                 optional_number(metric(&ErrorMetrics::weighted_relative_rmse)) +
                 ", \"memory_bytes\": " + optional_number(summary.memory_bytes) +
                 ", \"bake_points\": " + std::to_string(count) +
                 ", \"rays\": " + optional_number(summary.rays) +
                 ", \"report\": " + (best.report_json.empty() ? "null" : best.report_json) + "}";
    std::printf("%-10s %8lld %10.3f %12.6f %12.4g %14.4g\n", settings.method().c_str(),
                static_cast<long long>(samples), best.wall_seconds, error.value_or(-1.0),
                summary.rays.value_or(-1.0), summary.memory_bytes.value_or(-1.0));
    std::fflush(stdout);
  }

  std::ostringstream out;
  out << "{\n  \"scene\": " << json_quote(scene_path)
      << ",\n  \"reference\": " << json_quote(reference_path)
      << ",\n  \"metric\": \"relative RMSE over bake points, luminance-weighted (Rec. 709: "
         "0.2126, 0.7152, 0.0722)\""
      << ",\n  \"bakegi_version\": " << json_quote(bakegi_version_string())
      << ",\n  \"hardware_threads\": " << std::thread::hardware_concurrency()
      << ",\n  \"bake_points\": " << count << ",\n  \"runs\": [\n"
      << runs_json << "\n  ]\n}\n";
  write_output_file(out_path, out.str());
  std::fprintf(stderr, "wrote %s\n", out_path.c_str());
  return kExitOk;
}

}  // namespace bakegi::cli
