#include "bake/settings_check.h"

#include <variant>

#include "settings/setting_schema.h"
#include "settings/settings.h"
#include "solvers/method_registry.h"
#include "solvers/solver.h"
#include "util/error.h"

namespace bakegi {

std::string validated_method(Settings& settings) {
  apply_default_method_settings(settings);
  const auto method = settings.values().find("method");
  if (method != settings.values().end() && !std::holds_alternative<std::string>(method->second)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "setting \"method\" must be a string, got " +
                    std::string(method->second.index() == 0 ? "an integer" : "a float"));
  }
  const std::string name = method == settings.values().end()
                               ? std::string(kDefaultMethod)
                               : std::get<std::string>(method->second);
  settings.validate(method_schema(name), setting_keys_of_any_method());
  return name;
}

std::string check_bake_settings(Settings& settings) {
  const std::string method = validated_method(settings);
  make_solver(method)->check_settings(settings);
  return method;
}

}  // namespace bakegi
