#include "settings/setting_schema.h"

#include <algorithm>
#include <limits>

#include "settings/settings.h"
#include "util/report.h"

namespace bakegi {

SettingSpec integer_setting(std::string key, int64_t fallback, int64_t lo, int64_t hi,
                            SettingRole role, std::string doc) {
  SettingSpec s;
  s.key = std::move(key);
  s.type = SettingType::kInteger;
  s.fallback = fallback;
  s.int_lo = lo;
  s.int_hi = hi;
  s.role = role;
  s.doc = std::move(doc);
  return s;
}

SettingSpec number_setting(std::string key, double fallback, double lo, double hi,
                           SettingRole role, std::string doc) {
  SettingSpec s;
  s.key = std::move(key);
  s.type = SettingType::kNumber;
  s.fallback = fallback;
  s.lo = lo;
  s.hi = hi;
  s.role = role;
  s.doc = std::move(doc);
  return s;
}

SettingSpec text_setting(std::string key, std::string fallback, std::vector<std::string> choices,
                         SettingRole role, std::string doc) {
  SettingSpec s;
  s.key = std::move(key);
  s.type = SettingType::kText;
  s.fallback = std::move(fallback);
  s.choices = std::move(choices);
  s.role = role;
  s.doc = std::move(doc);
  return s;
}

const std::vector<SettingSpec>& common_setting_specs() {
  using R = SettingRole;
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  static const std::vector<SettingSpec> specs = {
      text_setting("method", kDefaultMethod, {}, R::kShapes,
                   "the method that bakes (`bakegi settings` lists them)"),
      integer_setting("samples", 64, 1, int64_t(1) << 30, R::kLighting,
                      "paths per bake point of a sampling method (and of the path tracer a "
                      "method hands a bake to, which takes 128 when none is given)"),
      integer_setting("seed", 0, 0, kMax, R::kShapes,
                      "random seed; results are deterministic for a seed"),
      integer_setting("sample_offset", 0, 0, int64_t(1) << 40, R::kShapes,
                      "index of the first sample: bakes of samples [o, o + n) average to one bake"),
      integer_setting("denoise", 0, 0, 1, R::kLighting,
                      "1: filter a sampling bake's noise over neighbouring points (edge- and "
                      "noise-aware; report \"denoise_noise_after\"): less noise for some bias, "
                      "which it estimates (\"denoise_local_bias\"); where the bias would "
                      "outweigh the noise it takes out the values stay unfiltered (warning); "
                      "0: off"),
      integer_setting("threads", 0, 0, 1024, R::kExecution, "worker threads, 0 = all cores"),
      integer_setting("memory_budget_mb", 4096, 1, int64_t(1) << 30, R::kShapes,
                      "a bake whose estimate exceeds it is refused; antiradiance coarsens an "
                      "automatic patch size to fit it (warning)"),
      // The self-check of every full bake: a few hundred probes give the NRMSE to within about
      // +-15% of itself where the error is well above the probes' noise (512 paths: 5-8% per
      // probe on the Cornell box and Sponza), for about a tenth of a path-traced bake's rays.
      integer_setting("error_probes", 256, 0, 65536, R::kShapes,
                      "bake points at which every full bake (not relights, not method direct) "
                      "compares its result with the path tracer's to estimate its own error "
                      "(report \"estimated_error\"); 0 = off"),
      integer_setting("error_probe_samples", 512, 16, int64_t(1) << 20, R::kShapes,
                      "paths per error probe"),
      integer_setting("fallback", 1, 0, 1, R::kShapes,
                      "1: a method that cannot model the scene hands the bake to the path tracer "
                      "with a warning (report \"method_used\"); 0: it fails instead"),
  };
  return specs;
}

SettingSchema::SettingSchema(std::string method, std::string summary,
                             const std::vector<const std::vector<SettingSpec>*>& parts)
    : method_(std::move(method)), summary_(std::move(summary)) {
  for (const std::vector<SettingSpec>* part : parts) {
    for (const SettingSpec& spec : *part) {
      auto same = std::find_if(specs_.begin(), specs_.end(),
                               [&](const SettingSpec& s) { return s.key == spec.key; });
      if (same != specs_.end()) {
        *same = spec;
      } else {
        specs_.push_back(spec);
      }
    }
  }
}

const SettingSpec* SettingSchema::find(const std::string& key) const {
  for (const SettingSpec& spec : specs_) {
    if (spec.key == key) return &spec;
  }
  return nullptr;
}

std::vector<std::string> SettingSchema::keys() const {
  std::vector<std::string> keys;
  for (const SettingSpec& spec : specs_) keys.push_back(spec.key);
  return keys;
}

std::vector<std::string> SettingSchema::keys_with_role(SettingRole role) const {
  std::vector<std::string> keys;
  for (const SettingSpec& spec : specs_) {
    if (spec.role == role) keys.push_back(spec.key);
  }
  return keys;
}

const char* role_name(SettingRole role) {
  switch (role) {
    case SettingRole::kShapes:
      return "shapes";
    case SettingRole::kLighting:
      return "lighting";
    case SettingRole::kExecution:
      return "execution";
  }
  return "?";
}

const char* type_name(SettingType type) {
  switch (type) {
    case SettingType::kInteger:
      return "integer";
    case SettingType::kNumber:
      return "number";
    case SettingType::kText:
      return "text";
  }
  return "?";
}

namespace {

std::string range_text(const SettingSpec& spec) {
  switch (spec.type) {
    case SettingType::kInteger:
      return std::to_string(spec.int_lo) + ".." + std::to_string(spec.int_hi);
    case SettingType::kNumber:
      return json_number(spec.lo) + ".." + json_number(spec.hi);
    case SettingType::kText: {
      std::string text;
      for (const std::string& c : spec.choices) text += (text.empty() ? "" : " | ") + c;
      return text.empty() ? "any text" : text;
    }
  }
  return "";
}

}  // namespace

std::string schema_json(const SettingSchema& schema) {
  std::string out = "{\"method\": " + json_quote(schema.method()) +
                    ", \"summary\": " + json_quote(schema.summary()) + ", \"settings\": [";
  for (size_t i = 0; i < schema.specs().size(); ++i) {
    const SettingSpec& s = schema.specs()[i];
    out += std::string(i ? ", " : "") + "{\"key\": " + json_quote(s.key) +
           ", \"type\": " + json_quote(type_name(s.type)) +
           ", \"default\": " + setting_to_json(s.fallback);
    if (s.type == SettingType::kInteger) {
      out += ", \"min\": " + std::to_string(s.int_lo) + ", \"max\": " + std::to_string(s.int_hi);
    } else if (s.type == SettingType::kNumber) {
      out += ", \"min\": " + json_number(s.lo) + ", \"max\": " + json_number(s.hi);
    } else {
      out += ", \"choices\": [";
      for (size_t c = 0; c < s.choices.size(); ++c) {
        out += std::string(c ? ", " : "") + json_quote(s.choices[c]);
      }
      out += "]";
    }
    out += ", \"role\": " + json_quote(role_name(s.role)) + ", \"doc\": " + json_quote(s.doc) + "}";
  }
  return out + "]}";
}

std::string schema_markdown(const SettingSchema& schema) {
  std::string out = "## `" + schema.method() + "`\n\n" + schema.summary() +
                    "\n\n| key | type | default | range | role | meaning |\n"
                    "|---|---|---|---|---|---|\n";
  for (const SettingSpec& s : schema.specs()) {
    std::string fallback = setting_to_json(s.fallback);
    if (fallback == "\"\"") fallback = "(empty)";
    out += "| `" + s.key + "` | " + type_name(s.type) + " | " + fallback + " | " + range_text(s) +
           " | " + role_name(s.role) + " | " + s.doc + " |\n";
  }
  return out;
}

const std::map<std::string, SettingValue>& default_method_settings() {
  static const std::map<std::string, SettingValue> settings = {
      {"target_error", 0.05}, {"denoise", int64_t(1)}, {"samples", int64_t(1) << 16}};
  return settings;
}

void apply_default_method_settings(Settings& settings) {
  if (settings.has("method")) return;
  for (const auto& [key, value] : default_method_settings()) {
    if (!settings.has(key)) settings.set(key, value);
  }
}

}  // namespace bakegi
