// A baked grid as a method: its registration.
#include "solvers/grid/grid_solver.h"
#include "solvers/method_registry.h"

namespace bakegi {

namespace {

std::unique_ptr<Solver> make_grid() {
  return std::make_unique<GridSolver>();
}

const MethodRegistration kRegistration(
    {"grid",
     "Indirect light read from a baked Irradiance Vector Grid (setting grid_file): no solve, "
     "milliseconds; each point reads the grid vertices it sees (docs/ivg.md).",
     60, false, make_grid, GridSolver::setting_specs});

}  // namespace

}  // namespace bakegi
