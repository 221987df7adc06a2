#include "report_summary.h"

#include <cstdio>

#include "json_value.h"

namespace bakegi::cli {
namespace {

// The first number stored under `key` anywhere in the report, depth first: counters live
// in a sub-object whose name is the report's business, not the CLI's.
std::optional<double> find_number(const JsonValue& value, const std::string& key) {
  const auto* object = std::get_if<JsonValue::Object>(&value.value);
  if (!object) return std::nullopt;
  if (const auto it = object->find(key); it != object->end() && it->second.number()) {
    return it->second.number();
  }
  for (const auto& [name, child] : *object) {
    if (const auto found = find_number(child, key)) return found;
  }
  return std::nullopt;
}

}  // namespace

ReportSummary summarize_report(const std::string& report_json) {
  ReportSummary summary;
  if (report_json.empty()) return summary;
  const JsonValue report = JsonValue::parse(report_json);
  summary.rays = find_number(report, "rays");
  summary.memory_bytes = find_number(report, "memory_bytes");
  if (const JsonValue* estimate = report.find("estimated_error")) {
    summary.estimated_error = estimate->number();
  }
  if (const JsonValue* interval = report.find("estimated_error_interval")) {
    if (const auto* bounds = std::get_if<JsonValue::Array>(&interval->value);
        bounds && bounds->size() == 2) {
      summary.estimated_error_low = (*bounds)[0].number();
      summary.estimated_error_high = (*bounds)[1].number();
    }
  }
  if (const JsonValue* seconds = report.find("seconds")) {
    if (const auto total = seconds->number()) {
      summary.core_seconds = total;
    } else if (const auto total_stage = find_number(*seconds, "total")) {
      summary.core_seconds = total_stage;
    } else if (const auto* stages = std::get_if<JsonValue::Object>(&seconds->value)) {
      double sum = 0.0;
      for (const auto& [stage, time] : *stages) sum += time.number().value_or(0.0);
      summary.core_seconds = sum;
    }
  }
  return summary;
}

std::string describe_estimated_error(const ReportSummary& summary) {
  if (!summary.estimated_error) return "";
  char text[160];
  const double e = 100.0 * *summary.estimated_error;
  if (summary.estimated_error_low && summary.estimated_error_high) {
    std::snprintf(text, sizeof text, "estimated error %.1f%% (%.1f-%.1f%%)", e,
                  100.0 * *summary.estimated_error_low, 100.0 * *summary.estimated_error_high);
  } else {
    std::snprintf(text, sizeof text, "estimated error %.1f%%", e);
  }
  std::string line = text;
  // The add-on's threshold (addon/bakegi/error_check.py).
  if (*summary.estimated_error > 0.10) {
    line += ": WARNING, above 10% (per object: the report's \"error_estimate\")";
  }
  return line;
}

}  // namespace bakegi::cli
