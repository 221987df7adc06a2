// The settings of one bake as the CLI collects them: named options (--method, --samples,
// --seed, --sample-offset, --threads, --max-bounces, --cache-dir) and any `--set key=value`,
// passed to the core unchanged so that it validates them (and new solvers' keys work at once).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "arguments.h"
#include "core_handles.h"

namespace bakegi::cli {

using SettingValue = std::variant<int64_t, double, std::string>;

class BakeSettings {
 public:
  void set(const std::string& key, SettingValue value);
  const std::vector<std::pair<std::string, SettingValue>>& entries() const { return entries_; }
  std::string method() const;      // the core's default method when not set
  SettingsHandle to_core() const;  // throws CoreError for a key or value the core refuses
  std::string to_json() const;

 private:
  std::vector<std::pair<std::string, SettingValue>> entries_;
};

// The option specs BakeSettings understands, for commands to add to theirs.
std::vector<OptionSpec> bake_setting_options();
// Reads them; `except` names options the command handles itself (sweep's --samples list).
BakeSettings bake_settings_from(const Arguments& args, const std::vector<std::string>& except = {});

}  // namespace bakegi::cli
