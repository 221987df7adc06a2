// What every solver shares: the refusal to relight, for methods that cannot.
#include "solvers/solver.h"

#include "util/error.h"

namespace bakegi {

std::unique_ptr<IndirectField> Solver::relight(const SolveInputs&, const Precomputation&,
                                               JobContext&) {
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "this method cannot relight; start a full bake (methods that can: antiradiance, "
              "meshless)");
}

}  // namespace bakegi
