// The solver lifecycle as a job runs it: check the settings, precompute (through the cache
// of bake/precomputation_store.h when the method has a codec and "cache_dir" is set), light;
// or solve, for methods without a precomputation. A relight lights a kept precomputation.
#pragma once

#include <memory>
#include <string>

#include "solvers/solver.h"

namespace bakegi {

struct SolverRun {
  std::unique_ptr<IndirectField> field;
  std::shared_ptr<const Precomputation> precomputation;  // null for methods without one
};

SolverRun run_solver(Solver& solver, const std::string& method, const SolveInputs& inputs,
                     JobContext& context);

std::unique_ptr<IndirectField> relight_solver(Solver& solver, const SolveInputs& inputs,
                                              std::shared_ptr<const Precomputation> kept,
                                              JobContext& context);

}  // namespace bakegi
