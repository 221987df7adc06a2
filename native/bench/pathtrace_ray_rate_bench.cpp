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
#include <vector>

#include "bench_scene.h"
#include "json_value.h"
#include "util/error.h"

namespace bakegi::bench {
namespace {

// A number of the report at a path of keys ({"rays"} is the top level's, not the error
// estimate's); 0 if absent.
double report_number(const cli::JsonValue& report, const std::vector<std::string>& path) {
  const cli::JsonValue* value = report.find_path(path);
  return value ? value->number().value_or(0.0) : 0.0;
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
    const cli::JsonValue report = cli::JsonValue::parse(job_report(job));
    // The error probes (on by default) trace the same paths in their own stage, counted
    // apart; leaving them out would charge their time to the bake's rays.
    rays += report_number(report, {"rays"}) + report_number(report, {"error_probe_rays"});
    // The stages where paths are traced: the field evaluated at the points, the probes.
    tracing_seconds += report_number(report, {"seconds", "evaluate"}) +
                       report_number(report, {"seconds", "error_estimate"});
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
