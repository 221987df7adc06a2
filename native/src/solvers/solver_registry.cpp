// The methods: one entry each (name, summary, whether it can hand a bake to the path tracer,
// factory, settings). Adding a method is a folder with its solver and its setting specs, and
// one entry here.
#include <map>
#include <memory>
#include <string>

#include "solvers/antiradiance/antiradiance_solver.h"
#include "solvers/direct_only/direct_only_solver.h"
#include "solvers/meshless/meshless_solver.h"
#include "solvers/pathtrace/path_trace_solver.h"
#include "solvers/solver.h"
#include "util/error.h"

namespace bakegi {

namespace {

const std::vector<SettingSpec>& no_specs() {
  static const std::vector<SettingSpec> none;
  return none;
}

struct MethodEntry {
  const char* name;
  const char* summary;
  bool hands_to_path_tracer;  // setting "fallback": its bake may be finished by the path tracer
  std::unique_ptr<Solver> (*make)();
  const std::vector<SettingSpec>& (*specs)();
};

template <class S>
std::unique_ptr<Solver> make() {
  return std::make_unique<S>();
}

const MethodEntry kMethods[] = {
    {"pathtrace", "Monte Carlo path tracing: the reference (DESIGN.md).", false,
     make<PathTraceSolver>, PathTraceSolver::setting_specs},
    {"direct",
     "Direct light only, E_direct / pi: what a Cycles Diffuse bake with only Direct writes "
     "(for checking light units against Cycles).",
     false, make<DirectOnlySolver>, no_specs},
    {"antiradiance",
     "Antiradiance (Dachsbacher et al. 2007): hierarchical transport without visibility rays, "
     "interpolated at the bake points; relights without relinking.",
     true, make<AntiradianceSolver>, AntiradianceSolver::setting_specs},
    {"meshless",
     "Meshless hierarchical basis with precomputed direct-to-indirect transfer (Lehtinen et al. "
     "2008); relights in milliseconds.",
     true, make<MeshlessSolver>, MeshlessSolver::setting_specs},
};

const MethodEntry& entry(const std::string& method) {
  for (const MethodEntry& e : kMethods) {
    if (method == e.name) return e;
  }
  std::string known;
  for (const MethodEntry& e : kMethods) known += (known.empty() ? "" : ", ") + std::string(e.name);
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "unknown method '" + method + "' (known: " + known + ")");
}

}  // namespace

std::unique_ptr<IndirectField> Solver::relight(const SolveInputs&, const Precomputation&,
                                               JobContext&) {
  throw Error(
      BAKEGI_ERROR_INVALID_ARGUMENT,
      "this method cannot relight; start a full bake (methods that can: antiradiance, meshless)");
}

std::unique_ptr<Solver> make_solver(const std::string& method) { return entry(method).make(); }

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const MethodEntry& e : kMethods) n.push_back(e.name);
    return n;
  }();
  return names;
}

const SettingSchema& method_schema(const std::string& method) {
  static const std::map<std::string, SettingSchema> schemas = [] {
    std::map<std::string, SettingSchema> all;
    for (const MethodEntry& e : kMethods) {
      std::vector<const std::vector<SettingSpec>*> parts = {&common_setting_specs()};
      if (e.hands_to_path_tracer) parts.push_back(&PathTraceSolver::setting_specs());
      parts.push_back(&e.specs());
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
    for (const MethodEntry& e : kMethods) {
      for (const std::string& key : method_schema(e.name).keys()) {
        if (std::find(all.begin(), all.end(), key) == all.end()) all.push_back(key);
      }
    }
    return all;
  }();
  return keys;
}

}  // namespace bakegi
