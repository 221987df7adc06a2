// Direct light only as a method: its registration (it has no settings of its own).
#include "solvers/direct_only/direct_only_solver.h"
#include "solvers/method_registry.h"

namespace bakegi {

namespace {

std::unique_ptr<Solver> make_direct() { return std::make_unique<DirectOnlySolver>(); }

const std::vector<SettingSpec>& no_settings() {
  static const std::vector<SettingSpec> none;
  return none;
}

const MethodRegistration kRegistration({
    "direct",
    "Direct light only, E_direct / pi: what a Cycles Diffuse bake with only Direct writes (for "
    "checking light units against Cycles).",
    20, false, make_direct, no_settings});

}  // namespace

}  // namespace bakegi
