// The "direct" method: E_direct / pi at the bake points, what a Cycles Diffuse bake with
// only Direct enabled (Color off) writes. Used to pin light units against Cycles.
// Settings: the common sampling ones (samples, seed, sample_offset); none of its own.
#pragma once

#include <memory>

#include "solvers/point_sampling.h"
#include "solvers/solver.h"

namespace bakegi {

class DirectLightField : public IndirectField {
 public:
  // `direct` (and the scene and tracer it refers to) must outlive the field.
  DirectLightField(const DirectLight& direct, const SampleSettings& settings);
  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override;

 private:
  const DirectLight& direct_;
  SampleSettings settings_;
};

class DirectOnlySolver : public Solver {
 public:
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;
};

}  // namespace bakegi
