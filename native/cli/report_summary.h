// The few figures of a core bake report (bakegi_job_get_report) that the sweep records:
// the core's own seconds, rays traced, memory.
#pragma once

#include <optional>
#include <string>

namespace bakegi::cli {

struct ReportSummary {
  std::optional<double> core_seconds;  // the core's total; sum of its stages if no total
  std::optional<double> rays;
  std::optional<double> memory_bytes;
};

// Missing figures stay empty; a report that is not JSON throws JsonError.
ReportSummary summarize_report(const std::string& report_json);

}  // namespace bakegi::cli
