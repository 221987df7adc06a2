// The registry the solver folders fill (method_registry.h): methods are looked up by name and
// listed by their listing order.
#include "solvers/method_registry.h"

#include <algorithm>
#include <map>

#include "solvers/solver.h"
#include "util/error.h"

namespace bakegi {

namespace {

// Filled while the library loads (static initialization of the *_method.cpp files), read
// only after: a function-local static, so that it exists before the first registration.
std::vector<MethodDescription>& registered() {
  static std::vector<MethodDescription> methods;
  return methods;
}

// The registered methods by listing order (then name, so that the order never depends on
// the order the linker placed the registrations in).
const std::vector<MethodDescription>& methods() {
  static const std::vector<MethodDescription> sorted = [] {
    std::vector<MethodDescription> all = registered();
    std::sort(all.begin(), all.end(), [](const MethodDescription& a, const MethodDescription& b) {
      return a.listing_order != b.listing_order ? a.listing_order < b.listing_order
                                                : std::string(a.name) < b.name;
    });
    return all;
  }();
  return sorted;
}

const MethodDescription& entry(const std::string& method) {
  for (const MethodDescription& e : methods()) {
    if (method == e.name) return e;
  }
  std::string known;
  for (const MethodDescription& e : methods()) {
    known += (known.empty() ? "" : ", ") + std::string(e.name);
  }
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "unknown method '" + method + "' (known: " + known + ")");
}

}  // namespace

MethodRegistration::MethodRegistration(const MethodDescription& method) {
  registered().push_back(method);
}

std::unique_ptr<Solver> make_solver(const std::string& method) { return entry(method).make(); }

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const MethodDescription& e : methods()) n.push_back(e.name);
    return n;
  }();
  return names;
}

const SettingSchema& method_schema(const std::string& method) {
  static const std::map<std::string, SettingSchema> schemas = [] {
    std::map<std::string, SettingSchema> all;
    for (const MethodDescription& e : methods()) {
      std::vector<const std::vector<SettingSpec>*> parts = {&common_setting_specs()};
      if (e.hands_to_path_tracer) parts.push_back(&entry("pathtrace").setting_specs());
      parts.push_back(&e.setting_specs());
      all.emplace(e.name, SettingSchema(e.name, e.summary, parts));
    }
    return all;
  }();
  entry(method);  // throws for an unknown method
  return schemas.at(method);
}

const std::vector<std::string>& setting_keys_of_any_method() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> all;
    for (const MethodDescription& e : methods()) {
      for (const std::string& key : method_schema(e.name).keys()) {
        if (std::find(all.begin(), all.end(), key) == all.end()) all.push_back(key);
      }
    }
    return all;
  }();
  return keys;
}

}  // namespace bakegi
