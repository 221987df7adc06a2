// Key/value bake settings as received through the C API. They are read through a method's
// schema (SettingReader): the schema gives every key's default and range, so a reader names
// only the key.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "settings/setting_schema.h"
#include "settings/setting_value.h"

namespace bakegi {

class Settings {
 public:
  Settings() = default;
  Settings(const Settings& other);
  Settings& operator=(const Settings& other);

  void set(const std::string& key, SettingValue value) { values_[key] = std::move(value); }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  const std::map<std::string, SettingValue>& values() const { return values_; }

  // Throws bakegi::Error(INVALID_ARGUMENT) for the first given key `schema` lacks ("unknown
  // setting" when no method reads it, listing `known_anywhere`; else "not read by method ...",
  // listing the schema's keys) and the first given value of the wrong type, outside its
  // range or not among its choices.
  void validate(const SettingSchema& schema, const std::vector<std::string>& known_anywhere) const;

  // The given values merged with every default that was read: what the bake really used.
  std::map<std::string, SettingValue> used_values() const;

 private:
  void remember(const std::string& key, const SettingValue& value) const;

  friend class SettingReader;

  std::map<std::string, SettingValue> values_;
  mutable std::mutex used_mutex_;  // solvers may read settings from several threads
  mutable std::map<std::string, SettingValue> used_;
};

// Reads settings with the defaults, ranges and choices of one method's schema
// (solvers/solver.h, method_schema). A key outside the schema is a bug: Error(INTERNAL). A
// given value of the wrong type or range: Error(INVALID_ARGUMENT). get_float also accepts an
// integer value. Every value read (given or default) is remembered in the settings
// (used_values), so the report and a precomputation's cache key see the defaults used.
class SettingReader {
 public:
  SettingReader(const Settings& settings, const SettingSchema& schema)
      : settings_(settings), schema_(schema) {}

  int64_t get_int(const std::string& key) const;
  double get_float(const std::string& key) const;
  std::string get_string(const std::string& key) const;

 private:
  // The given value checked against its spec, else the default; remembered either way.
  SettingValue read(const std::string& key, SettingType type) const;

  const Settings& settings_;
  const SettingSchema& schema_;
};

}  // namespace bakegi
