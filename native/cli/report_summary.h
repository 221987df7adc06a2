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
  // The bake's estimate of its own error (NRMSE, a fraction) and its 90% interval.
  std::optional<double> estimated_error;
  std::optional<double> estimated_error_low, estimated_error_high;
};

// "estimated error 4.6% (3.4-5.6%)", with a warning above 10%; empty without an estimate.
std::string describe_estimated_error(const ReportSummary& summary);

// Missing figures stay empty; a report that is not JSON throws JsonError.
ReportSummary summarize_report(const std::string& report_json);

}  // namespace bakegi::cli
