// What a bake setting is: its key, type, range or choices, default, role and meaning. Every
// method has one schema (settings common to all methods, the path tracer's when the method
// can hand a bake to it, and the method's own), and everything else is derived from it:
// validation when a job starts (an error names a key the method does not read), the
// defaults and ranges solvers read with (Settings::get_*), the keys a relight may change,
// the keys a precomputation cache ignores, and the settings reference (docs/settings.md,
// printed by `bakegi settings`, and bakegi_settings_describe in the C API).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "settings/setting_value.h"

namespace bakegi {

class Settings;

enum class SettingType { kInteger, kNumber, kText };

enum class SettingRole {
  kShapes,     // shapes what the method computes: a relight keeps it, a cache key holds it
  kLighting,   // used again when lighting: a relight may change it, a cache key ignores it
  kExecution,  // how the work runs (threads, cache folder), never what it computes
};

struct SettingSpec {
  std::string key;
  SettingType type = SettingType::kInteger;
  SettingValue fallback;  // the default
  int64_t int_lo = 0, int_hi = 0;     // inclusive range of kInteger values
  double lo = 0.0, hi = 0.0;          // inclusive range of kNumber values
  std::vector<std::string> choices;   // kText: the allowed values; empty = any text
  SettingRole role = SettingRole::kShapes;
  std::string doc;
};

SettingSpec integer_setting(std::string key, int64_t fallback, int64_t lo, int64_t hi,
                            SettingRole role, std::string doc);
SettingSpec number_setting(std::string key, double fallback, double lo, double hi,
                           SettingRole role, std::string doc);
SettingSpec text_setting(std::string key, std::string fallback, std::vector<std::string> choices,
                         SettingRole role, std::string doc);

// The method a bake uses when its settings name none: the "method" setting's default, the
// same in the core, the CLI and the add-on. With default_method_settings() it is the fastest
// bake to a 5% target on every scene measured (docs/benchmarks.md, section 0c: the path
// tracer through its denoiser lands at 4.2-5.7%; antiradiance misses 5% in the real rooms).
constexpr const char* kDefaultMethod = "pathtrace";

// What a bake that names no method also sets, where its settings do not: the target error
// (the add-on's Good quality), the denoiser, and the target's cap on paths per point.
const std::map<std::string, SettingValue>& default_method_settings();
// Adds default_method_settings() to `settings` if they name no method (keys they set stay).
void apply_default_method_settings(Settings& settings);

// Settings every method reads (through the job, the sampling loop or the error estimate).
const std::vector<SettingSpec>& common_setting_specs();

class SettingSchema {
 public:
  // `parts` in order; a later spec with the same key replaces an earlier one (a method may
  // give a common setting its own default or role).
  SettingSchema(std::string method, std::string summary,
                const std::vector<const std::vector<SettingSpec>*>& parts);

  const std::string& method() const { return method_; }
  const std::string& summary() const { return summary_; }
  const std::vector<SettingSpec>& specs() const { return specs_; }
  const SettingSpec* find(const std::string& key) const;
  std::vector<std::string> keys() const;
  std::vector<std::string> keys_with_role(SettingRole role) const;

 private:
  std::string method_, summary_;
  std::vector<SettingSpec> specs_;
};

const char* role_name(SettingRole role);
const char* type_name(SettingType type);

// The schema as JSON: {"method": ..., "summary": ..., "settings": [{"key", "type", "default",
// "min", "max", "choices", "role", "doc"}, ...]}.
std::string schema_json(const SettingSchema& schema);
// The schema as a Markdown table (docs/settings.md is these, one per method).
std::string schema_markdown(const SettingSchema& schema);

}  // namespace bakegi
