// bakegi_settings_*: values are stored as given; keys, types and ranges are checked when a
// job starts (BakeJob) and by the solvers that read them.
#include <cmath>

#include "api/api_guard.h"
#include "api/handles.h"

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
    *out_settings = new bakegi_settings();
  });
}

void bakegi_settings_destroy(bakegi_settings* settings) {
  delete settings;
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

}  // extern "C"
