// The path tracer's ray throughput on the benchmark scene, next to Embree's raw rate
// (embree_ray_rate_bench.cpp): a pathtrace job through the C API on all bake points at 16
// samples; rays/s = the report's "rays" and "error_probe_rays" (every ray traced: bounces
// and shadow rays, of the bake and of its error probes) over the job's wall time (BVH build
// included, as a user sees it), and over the time of the tracing stages alone
// (rays/s_tracing).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <string>

#include "bench_scene.h"
#include "util/error.h"

namespace bakegi::bench {
namespace {

// The number stored under `key` directly inside the JSON object that opens at `object`
// (a '{'), not in objects nested in it: the report has "rays" at the top level and inside
// "error_estimate". 0 if absent or not a number.
double number_in_object(const std::string& report, const std::string& key, size_t object = 0) {
  const std::string needle = "\"" + key + "\": ";
  int depth = 0;
  bool in_string = false;
  for (size_t i = object; i < report.size(); ++i) {
    const char c = report[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '{' || c == '[') {
      ++depth;
    } else if (c == '}' || c == ']') {
      if (--depth == 0) break;
    } else if (c == '"') {
      if (depth == 1 && report.compare(i, needle.size(), needle) == 0)
        return std::strtod(report.c_str() + i + needle.size(), nullptr);
      in_string = true;
    }
  }
  return 0.0;
}

// A stage's seconds, from the top-level object "seconds".
double stage_seconds(const std::string& report, const std::string& stage) {
  const size_t seconds = report.find("\"seconds\": {");
  if (seconds == std::string::npos) return 0.0;
  return number_in_object(report, stage, report.find('{', seconds));
}

std::string job_report(const bakegi_job* job) {
  size_t length = 0;
  bakegi_job_get_report(job, nullptr, 0, &length);
  std::string report(length + 1, '\0');
  bakegi_job_get_report(job, report.data(), report.size(), &length);
  report.resize(length);
  return report;
}

void BM_PathtraceJob(benchmark::State& state) {
  const int samples = int(state.range(0));
  const int threads = int(state.range(1));
  const CApiScene& c = bench_scene_c_api();
  bakegi_settings* settings = nullptr;
  bakegi_settings_create(&settings);
  bakegi_settings_set_string(settings, "method", "pathtrace");
  bakegi_settings_set_int(settings, "samples", samples);
  bakegi_settings_set_int(settings, "threads", threads);

  double rays = 0.0, seconds = 0.0, tracing_seconds = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    bakegi_job* job = nullptr;
    bakegi_status status = bakegi_job_start(c.scene, c.points, settings, &job);
    if (status == BAKEGI_OK) status = bakegi_job_wait(job);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (status != BAKEGI_OK) {
      state.SkipWithError(bakegi_last_error());
      bakegi_job_destroy(job);
      break;
    }
    state.SetIterationTime(wall);
    const std::string report = job_report(job);
    // The error probes (on by default) trace the same paths in their own stage, counted
    // apart; leaving them out would charge their time to the bake's rays.
    rays += number_in_object(report, "rays") + number_in_object(report, "error_probe_rays");
    // The stages where paths are traced: the field evaluated at the points, the probes.
    tracing_seconds += stage_seconds(report, "evaluate") + stage_seconds(report, "error_estimate");
    seconds += wall;
    bakegi_job_destroy(job);
  }
  bakegi_settings_destroy(settings);
  if (seconds > 0.0) {
    state.counters["rays/s"] = rays / seconds;
    if (tracing_seconds > 0.0) state.counters["rays/s_tracing"] = rays / tracing_seconds;
    state.counters["rays_per_job"] = rays / double(state.iterations());
    state.counters["points"] = double(bench_scene().points.size());
  }
  state.SetLabel(bench_scene().name);
}

BENCHMARK(BM_PathtraceJob)
    ->ArgNames({"samples", "threads"})
    // 16 samples: a job of a few tenths of a second, so that the BVH build (included, as
    // for a user) is a small part of it.
    ->Args({16, 1})
    ->Args({16, 2})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace bakegi::bench
