#include "util/settings.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"
#include "util/report.h"

namespace bakegi {

namespace {

const char* type_name(const SettingValue& value) {
  switch (value.index()) {
    case 0:
      return "an integer";
    case 1:
      return "a float";
    default:
      return "a string";
  }
}

[[noreturn]] void wrong_type(const std::string& key, const SettingValue& value,
                             const char* expected) {
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "setting \"" + key + "\" must be " + expected + ", got " + type_name(value));
}

}  // namespace

Settings::Settings(const Settings& other) : values_(other.values_) {
  std::lock_guard lock(other.used_mutex_);
  used_ = other.used_;
}

Settings& Settings::operator=(const Settings& other) {
  if (this == &other) return *this;
  std::map<std::string, SettingValue> used;
  {
    std::lock_guard lock(other.used_mutex_);
    used = other.used_;
  }
  values_ = other.values_;
  std::lock_guard lock(used_mutex_);
  used_ = std::move(used);
  return *this;
}

void Settings::remember(const std::string& key, const SettingValue& value) const {
  std::lock_guard lock(used_mutex_);
  used_[key] = value;
}

int64_t Settings::get_int(const std::string& key, int64_t fallback, int64_t lo, int64_t hi) const {
  auto it = values_.find(key);
  if (it == values_.end()) {
    remember(key, fallback);
    return fallback;
  }
  const int64_t* value = std::get_if<int64_t>(&it->second);
  if (!value) wrong_type(key, it->second, "an integer");
  if (*value < lo || *value > hi) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "setting \"" + key + "\" must be in [" +
                                                   std::to_string(lo) + ", " + std::to_string(hi) +
                                                   "], got " + std::to_string(*value));
  }
  remember(key, *value);
  return *value;
}

double Settings::get_float(const std::string& key, double fallback, double lo, double hi) const {
  auto it = values_.find(key);
  if (it == values_.end()) {
    remember(key, fallback);
    return fallback;
  }
  double value = 0.0;
  if (const double* d = std::get_if<double>(&it->second)) {
    value = *d;
  } else if (const int64_t* i = std::get_if<int64_t>(&it->second)) {
    value = static_cast<double>(*i);
  } else {
    wrong_type(key, it->second, "a number");
  }
  // Written so that NaN fails the test.
  if (!(value >= lo && value <= hi)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "setting \"" + key + "\" must be in [" +
                                                   json_number(lo) + ", " + json_number(hi) +
                                                   "], got " + json_number(value));
  }
  remember(key, value);
  return value;
}

std::string Settings::get_string(const std::string& key, const std::string& fallback) const {
  auto it = values_.find(key);
  if (it == values_.end()) {
    remember(key, fallback);
    return fallback;
  }
  const std::string* value = std::get_if<std::string>(&it->second);
  if (!value) wrong_type(key, it->second, "a string");
  remember(key, *value);
  return *value;
}

std::map<std::string, SettingValue> Settings::used_values() const {
  std::map<std::string, SettingValue> merged = values_;
  std::lock_guard lock(used_mutex_);
  for (const auto& [key, value] : used_) merged[key] = value;
  return merged;
}

void Settings::check_known_keys(const std::vector<std::string>& known) const {
  for (const auto& [key, value] : values_) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "unknown setting \"" + key + "\" (known settings: " + list + ")");
  }
}

const std::vector<std::string>& known_setting_keys() {
  static const std::vector<std::string> keys = {
      "method", "samples", "seed", "sample_offset", "threads", "max_bounces", "memory_budget_mb",
      "error_probes", "error_probe_samples", "fallback",
      // antiradiance
      "bins", "iterations", "tolerance", "scheme", "patch_size", "direct_samples", "oracle",
      "oracle_factor", "glossy_fold_exponent", "near_field_rays", "near_field_distance",
      // meshless
      "levels", "coarse_spacing", "sender_levels", "epsilon", "gather_rays", "bounces", "viewpoint",
      "visibility", "cache_dir", "sender_cutoff"};
  return keys;
}

std::string setting_to_json(const SettingValue& value) {
  if (const int64_t* i = std::get_if<int64_t>(&value)) return std::to_string(*i);
  if (const double* d = std::get_if<double>(&value)) return json_number(*d);
  return json_quote(std::get<std::string>(value));
}

}  // namespace bakegi
