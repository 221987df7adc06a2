// Runs one bake job through the C API: progress bar on stderr, Ctrl-C cancels, wall time
// measured from bakegi_job_start to the return of bakegi_job_wait.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bake_settings.h"
#include "core_handles.h"

namespace bakegi::cli {

struct BakeRun {
  std::vector<float> values;  // RGB per bake point
  std::string report_json;    // bakegi_job_get_report
  double wall_seconds = 0.0;
  JobHandle job;  // the finished job (a relight starts from it)
};

// Throws CoreError; a cancelled job throws with status BAKEGI_ERROR_CANCELLED.
BakeRun run_bake(const bakegi_scene* scene, const bakegi_points* points,
                 const BakeSettings& settings, const std::string& label);

// The same for a relight of `previous` (bakegi_job_start_relight) with the lights of `scene`.
BakeRun run_relight(const bakegi_job* previous, const bakegi_scene* scene, uint64_t point_count,
                    const bakegi_settings* overrides, const std::string& label);

// Runs the job `start` makes, for `point_count` bake points.
BakeRun run_job(const std::function<bakegi_status(bakegi_job**)>& start, uint64_t point_count,
                const std::string& label);

// The job's report, also after a failure (empty if the core has none).
std::string job_report(const bakegi_job* job);

}  // namespace bakegi::cli
