// bakegi_settings_*: values are stored as given; keys, types and ranges are checked against
// the method's schema when a job starts (BakeJob). bakegi_settings_describe hands the schemas
// out.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "api/api_guard.h"
#include "api/handles.h"
#include "api/text_output.h"
#include "bake/settings_check.h"
#include "settings/setting_schema.h"
#include "solvers/solver.h"
#include "util/report.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

namespace {

void require_key(const char* key) {
  require(key, "key");
  if (key[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "key is empty");
}

}  // namespace

extern "C" {

bakegi_status bakegi_settings_create(bakegi_settings** out_settings) {
  return guarded(__func__, [&] {
    require(out_settings, "out_settings");
    *out_settings = nullptr;
    *out_settings = bakegi::give_out(std::make_unique<bakegi_settings>());
  });
}

void bakegi_settings_destroy(bakegi_settings* settings) {
  bakegi::destroy_handle(settings);
}

bakegi_status bakegi_settings_set_int(bakegi_settings* settings, const char* key, int64_t value) {
  return guarded(__func__, [&] {
    require(settings, "settings");
    require_key(key);
    settings->settings.set(key, value);
  });
}

bakegi_status bakegi_settings_set_float(bakegi_settings* settings, const char* key, double value) {
  return guarded(__func__, [&] {
    require(settings, "settings");
    require_key(key);
    if (!std::isfinite(value)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, std::string("setting \"") + key + "\": value is " +
                                                     (std::isnan(value) ? "NaN" : "infinite"));
    }
    settings->settings.set(key, value);
  });
}

bakegi_status bakegi_settings_set_string(bakegi_settings* settings, const char* key,
                                         const char* value) {
  return guarded(__func__, [&] {
    require(settings, "settings");
    require_key(key);
    require(value, "value");
    settings->settings.set(key, std::string(value));
  });
}

bakegi_status bakegi_settings_check(const bakegi_settings* settings) {
  return guarded(__func__, [&] {
    require(settings, "settings");
    bakegi::Settings copy = settings->settings;  // the defaults it adds are not the caller's
    bakegi::check_bake_settings(copy);
  });
}

bakegi_status bakegi_settings_describe(const char* method, char* buffer, size_t capacity,
                                       size_t* out_length) {
  return guarded(__func__, [&] {
    bakegi::check_text_output(buffer, capacity, out_length);
    std::string json;
    if (!method || method[0] == '\0') {
      json = "{\"methods\": [";
      for (const std::string& name : bakegi::method_names()) {
        json += (json.back() == '[' ? "" : ", ") + bakegi::json_quote(name);
      }
      json += "], \"default\": " + bakegi::json_quote(bakegi::kDefaultMethod) +
              ", \"default_settings\": {";
      for (const auto& [key, value] : bakegi::default_method_settings()) {
        json += (json.back() == '{' ? "" : ", ") + bakegi::json_quote(key) + ": " +
                bakegi::setting_to_json(value);
      }
      json += "}}";
    } else {
      json = bakegi::schema_json(bakegi::method_schema(method));
    }
    bakegi::write_text_output(json, buffer, capacity, out_length);
  });
}

}  // extern "C"
