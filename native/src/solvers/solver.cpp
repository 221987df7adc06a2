// What every solver shares: the memory budget outside a job, the lifecycle's default
// (solve = light(precompute())), and the refusal to relight for methods that cannot.
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

std::shared_ptr<const Precomputation> Solver::precompute(const SolveInputs&, JobContext&) {
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "this method keeps no precomputation and cannot relight; start a full bake");
}

std::unique_ptr<IndirectField> Solver::light(const SolveInputs&,
                                             std::shared_ptr<const Precomputation>, JobContext&) {
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "this method keeps no precomputation and cannot relight; start a full bake");
}

std::unique_ptr<IndirectField> Solver::solve(const SolveInputs& inputs, JobContext& context) {
  return light(inputs, precompute(inputs, context), context);
}

}  // namespace bakegi
