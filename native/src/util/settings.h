// Key/value bake settings as received through the C API; solvers read them with defaults
// and ranges, and unknown keys are refused when a job starts.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <variant>

namespace bakegi {

using SettingValue = std::variant<int64_t, double, std::string>;

class Settings {
 public:
  void set(const std::string& key, SettingValue value) { values_[key] = std::move(value); }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  // Throw bakegi::Error(INVALID_ARGUMENT) on a wrong type or a value outside [lo, hi].
  int64_t get_int(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const;
  double get_float(const std::string& key, double fallback, double lo, double hi) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  const std::map<std::string, SettingValue>& values() const { return values_; }

 private:
  std::map<std::string, SettingValue> values_;
};

}  // namespace bakegi
