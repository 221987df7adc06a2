// Key/value bake settings as received through the C API; solvers read them with defaults
// and ranges, and unknown keys are refused when a job starts.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <variant>
#include <vector>

namespace bakegi {

using SettingValue = std::variant<int64_t, double, std::string>;

class Settings {
 public:
  Settings() = default;
  Settings(const Settings& other);
  Settings& operator=(const Settings& other);

  void set(const std::string& key, SettingValue value) { values_[key] = std::move(value); }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  // Throw bakegi::Error(INVALID_ARGUMENT) on a wrong type or a value outside [lo, hi].
  // get_float also accepts an integer value. Every value read (given or fallback) is
  // remembered for the report (used_values).
  int64_t get_int(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const;
  double get_float(const std::string& key, double fallback, double lo, double hi) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  const std::map<std::string, SettingValue>& values() const { return values_; }

  // The given values merged with every fallback that was read: what the bake really used.
  std::map<std::string, SettingValue> used_values() const;
  // Throws bakegi::Error(INVALID_ARGUMENT) naming the first key not in `known`.
  void check_known_keys(const std::vector<std::string>& known) const;

 private:
  void remember(const std::string& key, const SettingValue& value) const;

  std::map<std::string, SettingValue> values_;
  mutable std::mutex used_mutex_;  // solvers may read settings from several threads
  mutable std::map<std::string, SettingValue> used_;
};

// The setting keys a bake job understands (see bakegi.h).
const std::vector<std::string>& known_setting_keys();

// JSON text of a setting value ("pathtrace" quoted and escaped, numbers as numbers).
std::string setting_to_json(const SettingValue& value);

}  // namespace bakegi
