// Adaptive multiresolution splatting as a bake method (issue 17, item 6): one bounce of
// light from the reflective shadow maps' VPLs, gathered at the bake's points through a
// hierarchy of points refined at normal and position discontinuities (point_subsplats.h),
// the bake-point counterpart of the paper's subsplats. A fast one-bounce draft: the path
// tracer with max_bounces = 1 is its reference.
#pragma once

#include <memory>
#include <vector>

#include "solvers/solver.h"

namespace bakegi {

class SplattingSolver : public Solver {
 public:
  static const std::vector<SettingSpec>& setting_specs();
  void check_settings(const Settings& settings) const override;
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;
};

}  // namespace bakegi
