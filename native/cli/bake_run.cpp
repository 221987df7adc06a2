#include "bake_run.h"

#include <atomic>
#include <chrono>
#include <thread>

#include "interrupt.h"
#include "progress_bar.h"

namespace bakegi::cli {

std::string job_report(const bakegi_job* job) {
  size_t length = 0;
  if (bakegi_job_get_report(job, nullptr, 0, &length) != BAKEGI_OK) return "";
  std::string report(length + 1, '\0');
  if (bakegi_job_get_report(job, report.data(), report.size(), &length) != BAKEGI_OK) return "";
  report.resize(length);
  return report;
}

BakeRun run_bake(const bakegi_scene* scene, const bakegi_points* points,
                 const BakeSettings& settings, const std::string& label) {
  const SettingsHandle core_settings = settings.to_core();
  return run_job(
      [&](bakegi_job** out) { return bakegi_job_start(scene, points, core_settings.get(), out); },
      bakegi_points_count(points), label);
}

BakeRun run_relight(const bakegi_job* previous, const bakegi_scene* scene, uint64_t point_count,
                    const bakegi_settings* overrides, const std::string& label) {
  return run_job(
      [&](bakegi_job** out) {
        return bakegi_job_start_relight(previous, scene, nullptr, overrides, out);
      },
      point_count, label);
}

BakeRun run_job(const std::function<bakegi_status(bakegi_job**)>& start_job, uint64_t count,
                const std::string& label) {
  BakeRun run;
  const auto start = std::chrono::steady_clock::now();
  bakegi_job* raw = nullptr;
  check(start_job(&raw), "starting the bake");
  JobHandle job(raw);

  // The main thread blocks in bakegi_job_wait so the measured time ends when the job does;
  // a watcher thread draws progress and turns Ctrl-C into bakegi_job_cancel.
  std::atomic<bool> finished{false};
  std::thread watcher([&] {
    ProgressBar bar(label);
    char stage[128];
    while (!finished.load()) {
      if (interrupt_requested()) bakegi_job_cancel(job.get());
      bakegi_job_stage(job.get(), stage, sizeof stage);
      bar.update(bakegi_job_progress(job.get()), stage);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    bar.finish();
  });
  const bakegi_status status = bakegi_job_wait(job.get());
  run.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Keep the message before other calls can replace this thread's last error.
  const std::string message = status == BAKEGI_OK ? "" : bakegi_last_error();
  finished.store(true);
  watcher.join();

  if (status != BAKEGI_OK) {
    throw CoreError(status, "bake failed: " + message + " (" + bakegi_status_string(status) + ")");
  }
  run.values.resize(3 * count);
  if (count > 0) {  // a grid bake has no points
    check(bakegi_job_get_result(job.get(), run.values.data(), count), "reading the result");
  }
  run.report_json = job_report(job.get());
  run.job = std::move(job);
  return run;
}

}  // namespace bakegi::cli
