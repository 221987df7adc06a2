// The bake report: timings per stage, counters, memory, warnings; written out as JSON for
// the C API (bakegi_job_get_report), the add-on and the CLI.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "json_text.h"

namespace bakegi {

class Report {
 public:
  void add_seconds(const std::string& stage, double seconds);
  void set_number(const std::string& key, double value);
  void add_count(const std::string& key, uint64_t value);
  void set_text(const std::string& key, const std::string& value);
  // A value that is already JSON (an object such as "settings"); written as is.
  void set_json(const std::string& key, const std::string& json_value);
  void warn(const std::string& message);
  std::vector<std::string> warnings() const;
  uint64_t count(const std::string& key) const;  // 0 if never counted
  bool has_number(const std::string& key) const;
  double number(const std::string& key) const;  // 0 if never set
  // One JSON object: numbers, counts, texts and JSON values as top-level members,
  // "seconds": {stage: s, ...} and "warnings": [...]. Non-finite numbers become null.
  std::string to_json() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, double> seconds_;
  std::map<std::string, double> numbers_;
  std::map<std::string, uint64_t> counts_;
  std::map<std::string, std::string> texts_;
  std::map<std::string, std::string> json_values_;
  std::vector<std::string> warnings_;
};

}  // namespace bakegi
