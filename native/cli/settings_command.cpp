// bakegi settings [METHOD] [--markdown | --json]: the settings each method reads, from the
// core's schemas (bakegi_settings_describe): key, type, default, range or choices, role and
// meaning. `--markdown` without a method writes docs/settings.md.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "arguments.h"
#include "bakegi/bakegi.h"
#include "commands.h"
#include "core_handles.h"
#include "exit_codes.h"
#include "json_value.h"
#include "method_catalog.h"
#include "usage_error.h"

namespace bakegi::cli {
namespace {

std::string text_of(const JsonValue* value) {
  if (!value) return "";
  if (const auto s = value->string()) return *s;
  if (const auto n = value->number()) {
    if (*n >= 9.2e18) return "2^63-1";  // INT64_MAX, which a double cannot show exactly
    if (*n == std::floor(*n) && std::fabs(*n) < 1e15) return std::to_string(int64_t(*n));
    return json_number(*n);
  }
  return "";
}

std::string range_of(const JsonValue& setting) {
  if (const JsonValue* choices = setting.find("choices")) {
    std::string text;
    if (const auto* list = std::get_if<JsonValue::Array>(&choices->value)) {
      for (const JsonValue& c : *list) text += (text.empty() ? "" : " \\| ") + text_of(&c);
    }
    return text.empty() ? "any text" : text;
  }
  return text_of(setting.find("min")) + " .. " + text_of(setting.find("max"));
}

std::string default_of(const JsonValue& setting) {
  const JsonValue* fallback = setting.find("default");
  if (fallback && fallback->string()) {
    return fallback->string()->empty() ? "(empty)" : "\"" + *fallback->string() + "\"";
  }
  return text_of(fallback);
}

const JsonValue::Array& settings_of(const JsonValue& schema) {
  const JsonValue* settings = schema.find("settings");
  const auto* list = settings ? std::get_if<JsonValue::Array>(&settings->value) : nullptr;
  if (!list) throw JsonError("a schema without \"settings\"");
  return *list;
}

void print_markdown(const JsonValue& schema) {
  std::printf("## `%s`\n\n%s\n\n", text_of(schema.find("method")).c_str(),
              text_of(schema.find("summary")).c_str());
  std::printf("| key | type | default | range | role | meaning |\n|---|---|---|---|---|---|\n");
  for (const JsonValue& s : settings_of(schema)) {
    std::printf("| `%s` | %s | %s | %s | %s | %s |\n", text_of(s.find("key")).c_str(),
                text_of(s.find("type")).c_str(), default_of(s).c_str(), range_of(s).c_str(),
                text_of(s.find("role")).c_str(), text_of(s.find("doc")).c_str());
  }
  std::printf("\n");
}

void print_text(const JsonValue& schema) {
  std::printf("%s: %s\n", text_of(schema.find("method")).c_str(),
              text_of(schema.find("summary")).c_str());
  for (const JsonValue& s : settings_of(schema)) {
    std::printf("  %-22s %-8s default %-12s %-24s %-9s %s\n", text_of(s.find("key")).c_str(),
                text_of(s.find("type")).c_str(), default_of(s).c_str(), range_of(s).c_str(),
                text_of(s.find("role")).c_str(), text_of(s.find("doc")).c_str());
  }
  std::printf("\n");
}

constexpr const char* kMarkdownPreamble =
    "# Bake settings\n\n"
    "Made by `bakegi settings --markdown > docs/settings.md` from the core's schemas "
    "(`native/src/settings/`, each solver's `*_method.cpp`); a test checks that this "
    "file is current. Pass them as `--set key=value` to the CLI, as `method_settings` to "
    "`bakegi.bake()`, or with `bakegi_settings_set_*` in C. A job refuses a key its method "
    "does not read, a wrong type, and a value out of range.\n\n"
    "Roles: **shapes** (what the method computes; a relight keeps it, a precomputation cache "
    "is keyed by it), **lighting** (used again when lighting: a relight may change it, a cache "
    "ignores it), **execution** (how the work runs, never what it computes).\n\n";

// The method and the settings a bake gets when it names no method.
void print_default_recipe() {
  const JsonValue all = JsonValue::parse(describe_settings(nullptr));
  std::string settings;
  if (const JsonValue* given = all.find("default_settings")) {
    if (const auto* object = std::get_if<JsonValue::Object>(&given->value)) {
      for (const auto& [key, value] : *object) {
        const auto number = value.number();
        if (!number) continue;
        char text[64];
        std::snprintf(text, sizeof text, "%g", *number);
        settings += (settings.empty() ? "" : ", ") + ("`" + key + "` " + text);
      }
    }
  }
  std::printf("A bake that names no method bakes with `%s`%s%s (the fastest bake to a 5%% target "
              "on every scene measured: docs/benchmarks.md, section 0c).\n\n",
              default_method().c_str(), settings.empty() ? "" : " and, where not given, ",
              settings.c_str());
}

}  // namespace

int run_settings_command(const std::vector<std::string>& words) {
  const Arguments args(words, {{"markdown", false}, {"json", false}});
  if (args.positional().size() > 1) throw UsageError("settings expects at most one method");
  std::vector<std::string> methods;
  if (args.positional().empty()) {
    methods = method_names();
  } else {
    methods.push_back(args.positional()[0]);
  }
  if (args.has("markdown") && args.positional().empty()) {
    std::fputs(kMarkdownPreamble, stdout);
    print_default_recipe();
  }
  for (const std::string& method : methods) {
    const std::string json = describe_settings(method.c_str());
    if (args.has("json")) {
      std::printf("%s\n", json.c_str());
    } else if (args.has("markdown")) {
      print_markdown(JsonValue::parse(json));
    } else {
      print_text(JsonValue::parse(json));
    }
  }
  return kExitOk;
}

}  // namespace bakegi::cli
