// Runs one bake job through the C API: progress bar on stderr, Ctrl-C cancels, wall time
// measured from bakegi_job_start to the return of bakegi_job_wait.
#pragma once

#include <string>
#include <vector>

#include "bake_settings.h"
#include "core_handles.h"

namespace bakegi::cli {

struct BakeRun {
  std::vector<float> values;  // RGB per bake point
  std::string report_json;    // bakegi_job_get_report
  double wall_seconds = 0.0;
};

// Throws CoreError; a cancelled job throws with status BAKEGI_ERROR_CANCELLED.
BakeRun run_bake(const bakegi_scene* scene, const bakegi_points* points,
                 const BakeSettings& settings, const std::string& label);

// The job's report, also after a failure (empty if the core has none).
std::string job_report(const bakegi_job* job);

}  // namespace bakegi::cli
