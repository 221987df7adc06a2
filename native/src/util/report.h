// The bake report: timings per stage, counters, memory, warnings; written out as JSON for
// the C API (bakegi_job_get_report), the add-on and the CLI.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace bakegi {

class Report {
 public:
  void add_seconds(const std::string& stage, double seconds);
  void set_number(const std::string& key, double value);
  void add_count(const std::string& key, uint64_t value);
  void set_text(const std::string& key, const std::string& value);
  void warn(const std::string& message);
  std::string to_json() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, double> seconds_;
  std::map<std::string, double> numbers_;
  std::map<std::string, uint64_t> counts_;
  std::map<std::string, std::string> texts_;
  std::vector<std::string> warnings_;
};

}  // namespace bakegi
