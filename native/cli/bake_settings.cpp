#include "bake_settings.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>

#include "json_value.h"
#include "method_catalog.h"
#include "usage_error.h"

namespace bakegi::cli {
namespace {

// Options that map one to one onto integer settings of the core.
struct IntegerOption {
  const char* option;
  const char* key;
};
constexpr IntegerOption kIntegerOptions[] = {{"samples", "samples"},
                                             {"seed", "seed"},
                                             {"sample-offset", "sample_offset"},
                                             {"threads", "threads"},
                                             {"max-bounces", "max_bounces"}};

// "--set key=value": an integer if it reads as one, else a float, else a string.
SettingValue parse_setting_value(const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const long long i = std::strtoll(text.c_str(), &end, 10);
  if (!text.empty() && *end == '\0' && errno == 0) return static_cast<int64_t>(i);
  const double d = std::strtod(text.c_str(), &end);
  if (!text.empty() && *end == '\0') return d;
  return text;
}

}  // namespace

void BakeSettings::set(const std::string& key, SettingValue value) {
  const auto it = std::find_if(entries_.begin(), entries_.end(),
                               [&](const auto& entry) { return entry.first == key; });
  if (it != entries_.end()) {
    it->second = std::move(value);
  } else {
    entries_.emplace_back(key, std::move(value));
  }
}

std::string BakeSettings::method() const {
  for (const auto& [key, value] : entries_) {
    if (key == "method" && std::holds_alternative<std::string>(value)) {
      return std::get<std::string>(value);
    }
  }
  return default_method();
}

SettingsHandle BakeSettings::to_core() const {
  bakegi_settings* raw = nullptr;
  check(bakegi_settings_create(&raw), "creating settings");
  SettingsHandle settings(raw);
  for (const auto& [key, value] : entries_) {
    const std::string what = "setting '" + key + "'";
    if (const auto* i = std::get_if<int64_t>(&value)) {
      check(bakegi_settings_set_int(raw, key.c_str(), *i), what);
    } else if (const auto* d = std::get_if<double>(&value)) {
      check(bakegi_settings_set_float(raw, key.c_str(), *d), what);
    } else {
      check(bakegi_settings_set_string(raw, key.c_str(), std::get<std::string>(value).c_str()),
            what);
    }
  }
  return settings;
}

std::string BakeSettings::to_json() const {
  std::string out = "{";
  for (size_t n = 0; n < entries_.size(); ++n) {
    const auto& [key, value] = entries_[n];
    out += (n ? ", " : "") + json_quote(key) + ": ";
    if (const auto* i = std::get_if<int64_t>(&value)) {
      out += std::to_string(*i);
    } else if (const auto* d = std::get_if<double>(&value)) {
      out += json_number(*d);
    } else {
      out += json_quote(std::get<std::string>(value));
    }
  }
  return out + "}";
}

std::vector<OptionSpec> bake_setting_options() {
  std::vector<OptionSpec> specs = {{"method"}, {"cache-dir"}, {"set", true, true}};
  for (const auto& o : kIntegerOptions) specs.push_back({o.option});
  return specs;
}

BakeSettings bake_settings_from(const Arguments& args, const std::vector<std::string>& except) {
  BakeSettings settings;
  if (const auto method = args.value("method")) settings.set("method", *method);
  for (const auto& o : kIntegerOptions) {
    if (std::find(except.begin(), except.end(), o.option) != except.end()) continue;
    if (const auto text = args.value(o.option)) {
      // Range checks belong to the core; here only "is it a number".
      settings.set(o.key, parse_int(*text, std::string("--") + o.option, INT64_MIN, INT64_MAX));
    }
  }
  // A folder name stays text even when it reads as a number.
  if (const auto folder = args.value("cache-dir")) settings.set("cache_dir", *folder);
  for (const auto& assignment : args.values("set")) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw UsageError("--set expects key=value, got '" + assignment + "'");
    }
    settings.set(assignment.substr(0, eq), parse_setting_value(assignment.substr(eq + 1)));
  }
  return settings;
}

}  // namespace bakegi::cli
