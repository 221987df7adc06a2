// The methods a bake can use. Each solver folder registers its own method in its
// *_method.cpp (name, summary, factory, settings) with a MethodRegistration; nothing else
// lists the methods, so adding one touches no file outside its folder.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "settings/setting_schema.h"

namespace bakegi {

class Solver;

struct MethodDescription {
  const char* name;
  const char* summary;
  // Where the method stands in listings (method_names, docs/settings.md): lower first.
  int listing_order;
  // Setting "fallback": a bake the method cannot model may be finished by the path tracer,
  // so the path tracer's settings join the method's schema.
  bool hands_to_path_tracer;
  std::unique_ptr<Solver> (*make)();
  const std::vector<SettingSpec>& (*setting_specs)();
};

// Registers a method while the library loads. One per method, at namespace scope:
//   const MethodRegistration kRegistration({"name", "summary", 30, false, make, specs});
// The library is linked from whole object files (CMakeLists.txt), so no registration is
// dropped by the linker.
class MethodRegistration {
 public:
  explicit MethodRegistration(const MethodDescription& method);
};

// Throws bakegi::Error(INVALID_ARGUMENT) for an unknown method name.
std::unique_ptr<Solver> make_solver(const std::string& method);
// The names of the methods, by listing order.
const std::vector<std::string>& method_names();
// A method's settings: the common ones, the path tracer's when the method can hand a bake to
// it (setting "fallback"), then its own. Throws Error(INVALID_ARGUMENT) for an unknown method.
const SettingSchema& method_schema(const std::string& method);
// Every key some method reads (to tell an unknown key from one another method reads).
const std::vector<std::string>& setting_keys_of_any_method();

}  // namespace bakegi
