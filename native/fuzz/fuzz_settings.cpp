// libFuzzer target: settings as text reach the core (the CLI's `--set key=value`, the
// add-on's method_settings): each input line "key=value" becomes an integer, number or
// text setting as the CLI types it, then the job's checks run: the schema of the method the
// settings name, and the solver reading every setting it uses (Solver::check_settings).
#include <charconv>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>

#include "fuzz_input.h"
#include "settings/setting_schema.h"
#include "settings/settings.h"
#include "solvers/method_registry.h"
#include "solvers/solver.h"

namespace {

bakegi::SettingValue typed_value(std::string_view text) {
  int64_t integer = 0;
  const char* end = text.data() + text.size();
  auto [int_end, int_error] = std::from_chars(text.data(), end, integer);
  if (int_error == std::errc() && int_end == end && !text.empty()) return integer;
  double number = 0.0;
  auto [float_end, float_error] = std::from_chars(text.data(), end, number);
  // The C API refuses non-finite numbers before they are stored (bakegi_settings_set_float).
  if (float_error == std::errc() && float_end == end && std::isfinite(number)) return number;
  return std::string(text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace bakegi;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Settings settings;
  size_t line_start = 0;
  while (line_start < text.size()) {
    size_t line_end = text.find('\n', line_start);
    if (line_end == std::string_view::npos) line_end = text.size();
    const std::string_view line = text.substr(line_start, line_end - line_start);
    line_start = line_end + 1;
    const size_t equals = line.find('=');
    if (equals == std::string_view::npos || equals == 0) continue;  // the C API wants a key
    settings.set(std::string(line.substr(0, equals)), typed_value(line.substr(equals + 1)));
  }
  fuzz::refused_or_read([&] {
    apply_default_method_settings(settings);
    std::string method = kDefaultMethod;
    if (settings.has("method")) {
      const SettingValue& named = settings.values().at("method");
      if (const std::string* name = std::get_if<std::string>(&named)) method = *name;
    }
    const SettingSchema& schema = method_schema(method);
    settings.validate(schema, setting_keys_of_any_method());
    make_solver(method)->check_settings(settings);
    const SettingReader reader(settings, schema);
    for (const SettingSpec& spec : schema.specs()) {
      if (spec.type == SettingType::kInteger) reader.get_int(spec.key);
      if (spec.type == SettingType::kNumber) reader.get_float(spec.key);
      if (spec.type == SettingType::kText) reader.get_string(spec.key);
    }
  });
  return 0;
}
