#include <memory>
#include <string>

#include "solvers/antiradiance/antiradiance_solver.h"
#include "solvers/direct_only/direct_only_solver.h"
#include "solvers/meshless/meshless_solver.h"
#include "solvers/pathtrace/path_tracer.h"
#include "solvers/solver.h"
#include "util/error.h"

namespace bakegi {

std::unique_ptr<IndirectField> Solver::relight(const SolveInputs&, const Precomputation&,
                                               JobContext&) {
  throw Error(
      BAKEGI_ERROR_INVALID_ARGUMENT,
      "this method cannot relight; start a full bake (methods that can: antiradiance, meshless)");
}

std::unique_ptr<Solver> make_solver(const std::string& method) {
  if (method == "pathtrace") return std::make_unique<PathTracer>();
  if (method == "direct") return std::make_unique<DirectOnlySolver>();
  if (method == "antiradiance") return std::make_unique<AntiradianceSolver>();
  if (method == "meshless") return std::make_unique<MeshlessSolver>();
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "unknown method '" + method + "' (known: pathtrace, direct, antiradiance, meshless)");
}

}  // namespace bakegi
