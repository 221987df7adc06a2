#include "method_catalog.h"

#include "bakegi/bakegi.h"
#include "core_handles.h"
#include "json_value.h"

namespace bakegi::cli {

std::string describe_settings(const char* method) {
  size_t length = 0;
  check(bakegi_settings_describe(method, nullptr, 0, &length), "describing settings");
  std::string text(length + 1, '\0');
  check(bakegi_settings_describe(method, text.data(), text.size(), nullptr), "describing settings");
  text.resize(length);
  return text;
}

std::vector<std::string> method_names() {
  const JsonValue all = JsonValue::parse(describe_settings(nullptr));
  const JsonValue* names = all.find("methods");
  const auto* list = names ? std::get_if<JsonValue::Array>(&names->value) : nullptr;
  if (!list) throw JsonError("the core's method list has no \"methods\"");
  std::vector<std::string> out;
  for (const JsonValue& name : *list) {
    if (const auto text = name.string()) out.push_back(*text);
  }
  return out;
}

std::string default_method() {
  const JsonValue all = JsonValue::parse(describe_settings(nullptr));
  const JsonValue* name = all.find("default");
  const auto text = name ? name->string() : std::nullopt;
  if (!text) throw JsonError("the core's method list has no \"default\"");
  return *text;
}

}  // namespace bakegi::cli
