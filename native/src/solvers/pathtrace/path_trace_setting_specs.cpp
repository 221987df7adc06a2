// The path tracer's own settings (the sampling ones are common: settings/setting_schema.cpp).
#include "solvers/pathtrace/path_trace_solver.h"

namespace bakegi {

const std::vector<SettingSpec>& PathTraceSolver::setting_specs() {
  static const std::vector<SettingSpec> specs = {
      integer_setting("max_bounces", 64, 1, 1 << 16, SettingRole::kShapes,
                      "path length cap for indirect light (Russian roulette ends most paths far "
                      "sooner)"),
  };
  return specs;
}

}  // namespace bakegi
