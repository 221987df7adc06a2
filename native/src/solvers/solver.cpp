// What every solver shares: the memory budget outside a job, and the refusal to relight for
// methods that cannot.
#include "solvers/solver.h"

#include "scene/ray_tracer.h"
#include "settings/settings.h"
#include "util/error.h"

namespace bakegi {

MemoryBudget memory_budget_for(const Settings& settings, const RayTracer& tracer) {
  // memory_budget_mb is a common key: every method's schema reads it the same way.
  const SettingReader reader(settings, method_schema("pathtrace"));
  MemoryBudget budget(uint64_t(reader.get_int("memory_budget_mb")) << 20);
  budget.hold(tracer.memory_bytes());
  return budget;
}

std::unique_ptr<IndirectField> Solver::relight(const SolveInputs&, const Precomputation&,
                                               JobContext&) {
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "this method cannot relight; start a full bake (methods that can: antiradiance, "
              "meshless)");
}

}  // namespace bakegi
