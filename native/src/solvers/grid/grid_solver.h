// A baked Irradiance Vector Grid as a bake method (issue 16, item 2: the grid behind the
// same field interface as the solvers): no solve, the field reads the grid file at whatever
// points the bake has (face corners, vertices, lightmap texels), as Apply Grid does
// (grid/grid_visibility.h: each point reads the vertices it sees, buried points read 0), or
// as the paper does (grid_visibility = 0).
#pragma once

#include <memory>
#include <vector>

#include "solvers/solver.h"

namespace bakegi {

struct IrradianceVectorGrid;

class GridSolver : public Solver {
 public:
  static const std::vector<SettingSpec>& setting_specs();
  void check_settings(const Settings& settings) const override;
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;
};

}  // namespace bakegi
