#include "util/report.h"

#include <cmath>
#include <cstdio>

namespace bakegi {

void Report::add_seconds(const std::string& stage, double seconds) {
  std::lock_guard lock(mutex_);
  seconds_[stage] += seconds;
}

void Report::set_number(const std::string& key, double value) {
  std::lock_guard lock(mutex_);
  numbers_[key] = value;
}

void Report::add_count(const std::string& key, uint64_t value) {
  std::lock_guard lock(mutex_);
  counts_[key] += value;
}

void Report::set_text(const std::string& key, const std::string& value) {
  std::lock_guard lock(mutex_);
  texts_[key] = value;
}

void Report::set_json(const std::string& key, const std::string& json_value) {
  std::lock_guard lock(mutex_);
  json_values_[key] = json_value;
}

void Report::warn(const std::string& message) {
  std::lock_guard lock(mutex_);
  warnings_.push_back(message);
}

std::vector<std::string> Report::warnings() const {
  std::lock_guard lock(mutex_);
  return warnings_;
}

bool Report::has_number(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return numbers_.count(key) > 0;
}

double Report::number(const std::string& key) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto found = numbers_.find(key);
  return found == numbers_.end() ? 0.0 : found->second;
}

uint64_t Report::count(const std::string& key) const {
  std::lock_guard lock(mutex_);
  auto it = counts_.find(key);
  return it == counts_.end() ? 0 : it->second;
}

std::string Report::to_json() const {
  std::lock_guard lock(mutex_);
  // One member per key: later kinds win if a key was used twice, so the output stays a
  // valid object with unique names.
  std::map<std::string, std::string> members;
  for (const auto& [key, value] : numbers_) members[key] = json_number(value);
  for (const auto& [key, value] : counts_) members[key] = std::to_string(value);
  for (const auto& [key, value] : texts_) members[key] = json_quote(value);
  for (const auto& [key, value] : json_values_) members[key] = value;
  std::string seconds = "{";
  for (const auto& [stage, value] : seconds_) {
    if (seconds.size() > 1) seconds += ", ";
    seconds += json_quote(stage) + ": " + json_number(value);
  }
  members["seconds"] = seconds + "}";
  std::string warnings = "[";
  for (const std::string& warning : warnings_) {
    if (warnings.size() > 1) warnings += ", ";
    warnings += json_quote(warning);
  }
  members["warnings"] = warnings + "]";

  std::string json = "{";
  for (const auto& [key, value] : members) {
    if (json.size() > 1) json += ", ";
    json += json_quote(key) + ": " + value;
  }
  return json + "}";
}


}  // namespace bakegi
