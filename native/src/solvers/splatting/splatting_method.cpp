// Adaptive multiresolution splatting as a method: its registration.
#include "solvers/method_registry.h"
#include "solvers/splatting/splatting_solver.h"

namespace bakegi {

namespace {

std::unique_ptr<Solver> make_splatting() {
  return std::make_unique<SplattingSolver>();
}

const MethodRegistration kRegistration(
    {"splatting",
     "Nichols & Wyman 2009: one bounce from reflective-shadow-map VPLs, gathered through a "
     "hierarchy refined at discontinuities; no visibility for the bounce unless "
     "visibility_clusters > 0. A fast one-bounce draft (docs/methods/splatting.md).",
     50, false, make_splatting, SplattingSolver::setting_specs});

}  // namespace

}  // namespace bakegi
