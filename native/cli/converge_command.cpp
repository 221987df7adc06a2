// bakegi converge scene.bgs --iterations K [--reference-iterations R] --out convergence.json
//                           [settings]
// The convergence study of Antiradiance Fig. 5: the error after k = 1..K iterations of the
// symmetric and of the asymmetric scheme, against a solution iterated R times (tolerance 0).
// Bakes once (R iterations, symmetric) and relights from that bake for every (scheme, k),
// so hierarchy and links are shared and only the iteration count differs. Error is the
// project's metric over the scene file's bake points (relative RMSE, luminance-weighted).
// Writes JSON: per scheme, per k, the error, the relight's seconds, the scheme that produced
// the result (a diverging symmetric run is solved again by the asymmetric scheme) and, for
// the last k, the core's residual history (the flux each iteration added, relative).
#include <cstdio>
#include <string>

#include "arguments.h"
#include "bake_run.h"
#include "bake_settings.h"
#include "commands.h"
#include "error_metric.h"
#include "exit_codes.h"
#include "file_error.h"
#include "json_value.h"
#include "scene_file.h"
#include "usage_error.h"

namespace bakegi::cli {

namespace {

SettingsHandle iteration_settings(int64_t iterations, const char* scheme) {
  bakegi_settings* raw = nullptr;
  check(bakegi_settings_create(&raw), "creating settings");
  SettingsHandle settings(raw);
  check(bakegi_settings_set_int(raw, "iterations", iterations), "setting iterations");
  check(bakegi_settings_set_float(raw, "tolerance", 0.0), "setting tolerance");
  check(bakegi_settings_set_string(raw, "scheme", scheme), "setting scheme");
  return settings;
}

// The scheme that produced the result ("antiradiance_scheme"): the symmetric scheme falls
// back to the asymmetric one when it diverges.
std::string scheme_of(const std::string& report) {
  const JsonValue json = JsonValue::parse(report);
  const JsonValue* scheme = json.find("antiradiance_scheme");
  return scheme ? scheme->string().value_or("") : "";
}

// The "antiradiance_residuals" array of a report, as JSON text ("[]" when absent).
std::string residuals_of(const std::string& report) {
  const JsonValue json = JsonValue::parse(report);
  const JsonValue* residuals = json.find("antiradiance_residuals");
  std::string text = "[";
  if (residuals) {
    if (const auto* array = std::get_if<JsonValue::Array>(&residuals->value)) {
      for (const JsonValue& value : *array) {
        if (text.size() > 1) text += ", ";
        text += json_number(value.number().value_or(0.0));
      }
    }
  }
  return text + "]";
}

}  // namespace

int run_converge_command(const std::vector<std::string>& words) {
  std::vector<OptionSpec> specs = bake_setting_options();
  specs.push_back({"out"});
  specs.push_back({"iterations"});
  specs.push_back({"reference-iterations"});
  const Arguments args(words, specs);
  if (args.positional().size() != 1) throw UsageError("converge expects one scene file");
  const std::string out_path = args.require("out");
  check_output_folder(out_path);
  const int64_t iterations = args.int_value("iterations", 40, 1, 10000);
  const int64_t reference_iterations =
      args.int_value("reference-iterations", 300, iterations, 100000);
  BakeSettings settings = bake_settings_from(args, {"iterations"});
  if (settings.method() != "antiradiance") {
    throw UsageError("converge studies the antiradiance iteration: pass --method antiradiance");
  }
  settings.set("iterations", reference_iterations);
  settings.set("tolerance", 0.0);
  settings.set("scheme", std::string("symmetric"));

  const SceneFile file = load_scene_file_with_points(args.positional()[0]);
  const uint64_t count = bakegi_points_count(file.points.get());
  const BakeRun reference = run_bake(file.scene.get(), file.points.get(), settings, "reference");

  std::string json = "{\"points\": " + std::to_string(count) +
                     ", \"reference_iterations\": " + std::to_string(reference_iterations) +
                     ", \"reference_seconds\": " + std::to_string(reference.wall_seconds) +
                     ", \"reference_residuals\": " + residuals_of(reference.report_json) +
                     ", \"reference_scheme\": " + json_quote(scheme_of(reference.report_json)) +
                     ", \"settings\": " + settings.to_json() + ", \"schemes\": {";
  const char* schemes[] = {"symmetric", "asymmetric"};
  for (int s = 0; s < 2; ++s) {
    json += std::string(s ? ", " : "") + "\"" + schemes[s] + "\": [";
    for (int64_t k = 1; k <= iterations; ++k) {
      const SettingsHandle overrides = iteration_settings(k, schemes[s]);
      const BakeRun run = run_relight(reference.job.get(), file.scene.get(), count, overrides.get(),
                                      std::string(schemes[s]) + " " + std::to_string(k));
      const auto error = relative_rmse_luminance(run.values.data(), reference.values.data(), count);
      char entry[128];
      std::snprintf(entry, sizeof entry,
                    "{\"iterations\": %lld, \"error\": %.9g, \"seconds\": %.6f",
                    static_cast<long long>(k), error ? *error : -1.0, run.wall_seconds);
      json += std::string(k > 1 ? ", " : "") + entry;
      json += ", \"scheme_used\": " + json_quote(scheme_of(run.report_json));
      if (k == iterations) json += ", \"residuals\": " + residuals_of(run.report_json);
      json += "}";
    }
    json += "]";
  }
  json += "}}";

  write_output_file(out_path, json + "\n");
  std::fprintf(stderr, "wrote %s\n", out_path.c_str());
  return kExitOk;
}

}  // namespace bakegi::cli
