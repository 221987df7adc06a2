#include "settings/settings.h"

#include <algorithm>
#include <cmath>

#include "settings/setting_schema.h"
#include "util/error.h"
#include "util/report.h"

namespace bakegi {

namespace {

const char* value_type_name(const SettingValue& value) {
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
              "setting \"" + key + "\" must be " + expected + ", got " + value_type_name(value));
}

std::string listed(const std::vector<std::string>& keys) {
  std::string list;
  for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
  return list;
}

// "a" | "a" or "b" | "a", "b" or "c"
std::string alternatives(const std::vector<std::string>& choices) {
  std::string text;
  for (size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) text += i + 1 == choices.size() ? " or " : ", ";
    text += "\"" + choices[i] + "\"";
  }
  return text;
}

// Checks a given value against its spec; returns it as the spec's type.
SettingValue checked(const SettingSpec& spec, const SettingValue& given) {
  switch (spec.type) {
    case SettingType::kInteger: {
      const int64_t* value = std::get_if<int64_t>(&given);
      if (!value) wrong_type(spec.key, given, "an integer");
      if (*value < spec.int_lo || *value > spec.int_hi) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "setting \"" + spec.key + "\" must be in [" + std::to_string(spec.int_lo) +
                        ", " + std::to_string(spec.int_hi) + "], got " + std::to_string(*value));
      }
      return *value;
    }
    case SettingType::kNumber: {
      double value = 0.0;
      if (const double* d = std::get_if<double>(&given)) {
        value = *d;
      } else if (const int64_t* i = std::get_if<int64_t>(&given)) {
        value = static_cast<double>(*i);
      } else {
        wrong_type(spec.key, given, "a number");
      }
      // Written so that NaN fails the test.
      if (!(value >= spec.lo && value <= spec.hi)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "setting \"" + spec.key + "\" must be in [" + json_number(spec.lo) + ", " +
                        json_number(spec.hi) + "], got " + json_number(value));
      }
      return value;
    }
    case SettingType::kText: {
      const std::string* value = std::get_if<std::string>(&given);
      if (!value) wrong_type(spec.key, given, "a string");
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), *value) == spec.choices.end()) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "setting \"" + spec.key + "\" must be " +
                                                       alternatives(spec.choices) + ", not \"" +
                                                       *value + "\"");
      }
      return *value;
    }
  }
  throw Error(BAKEGI_ERROR_INTERNAL, "setting \"" + spec.key + "\" has no type");
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

void Settings::validate(const SettingSchema& schema,
                        const std::vector<std::string>& known_anywhere) const {
  for (const auto& [key, value] : values_) {
    const SettingSpec* spec = schema.find(key);
    if (spec) {
      checked(*spec, value);
      continue;
    }
    if (std::find(known_anywhere.begin(), known_anywhere.end(), key) == known_anywhere.end()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "unknown setting \"" + key +
                                                     "\" (known settings: " +
                                                     listed(known_anywhere) + ")");
    }
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "setting \"" + key + "\" is not read by method \"" + schema.method() +
                    "\" (its settings: " + listed(schema.keys()) + ")");
  }
}

namespace {

const SettingSpec& spec_of(const SettingSchema& schema, const std::string& key,
                           SettingType type) {
  const SettingSpec* spec = schema.find(key);
  if (!spec || spec->type != type) {
    throw Error(BAKEGI_ERROR_INTERNAL, "setting \"" + key + "\" is not a " + type_name(type) +
                                           " setting of method \"" + schema.method() + "\"");
  }
  return *spec;
}

}  // namespace

SettingValue SettingReader::read(const std::string& key, SettingType type) const {
  const SettingSpec& spec = spec_of(schema_, key, type);
  auto it = settings_.values_.find(key);
  SettingValue value = it == settings_.values_.end() ? spec.fallback : checked(spec, it->second);
  settings_.remember(key, value);
  return value;
}

int64_t SettingReader::get_int(const std::string& key) const {
  return std::get<int64_t>(read(key, SettingType::kInteger));
}

double SettingReader::get_float(const std::string& key) const {
  return std::get<double>(read(key, SettingType::kNumber));
}

std::string SettingReader::get_string(const std::string& key) const {
  return std::get<std::string>(read(key, SettingType::kText));
}

std::map<std::string, SettingValue> Settings::used_values() const {
  std::map<std::string, SettingValue> merged = values_;
  std::lock_guard lock(used_mutex_);
  for (const auto& [key, value] : used_) merged[key] = value;
  return merged;
}

std::string setting_to_json(const SettingValue& value) {
  if (const int64_t* i = std::get_if<int64_t>(&value)) return std::to_string(*i);
  if (const double* d = std::get_if<double>(&value)) return json_number(*d);
  return json_quote(std::get<std::string>(value));
}

}  // namespace bakegi
