// The meshless solver ("meshless", Lehtinen et al. 2008): precomputed direct-to-indirect
// transfer in a meshless hierarchical basis. solve() precomputes (point placement §2.3,
// basis §2.1-2.2, the operator T by adaptive refinement §3.2, S = T + T² + … §3.1) and then
// lights (§3.3); relight() reuses the precomputation and only lights: direct light at the
// sender points, e = P† E, i = S e. The field evaluates the indirect vector irradiance i at
// bake points through the basis (Eq. 6) and dots it with their normals.
//
// Settings (read with ranges; a bad value fails before any work):
//   levels          receiver levels L + 1, 0 = automatic (point_placement.h: 4)
//   coarse_spacing  R_coarse in metres, 0 = automatic
//   sender_levels   sender levels (the first ones), 0 = automatic: half the receiver levels,
//                   rounded up (the paper: 6 receiver / 3 sender levels)
//   epsilon         the link threshold ε in the paper's units (default 0.01; the paper's 0.025
//                   drops links that carry energy here: Cornell 7.8% -> 6.3% at 0.01)
//   gather_rays     hemisphere rays per receiver of Eq. 16 (default 256)
//   bounces         bounces at most, the first included (default 16; the paper simulated 4)
//   direct_samples  direct-light samples per sender point (default 16)
//   viewpoint       "x,y,z": importance particles start there (§2.3); empty (default): they
//                   leave the bake points, which define the surfaces that matter for a bake
//   visibility      1 (default): at bake points, leave out basis functions whose point the
//                   bake point cannot see (visible_evaluation.h); 0: plain Eq. 6
//   seed, memory_budget_mb
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "solvers/solver.h"

namespace bakegi {

struct MeshlessPrecomputation;

class MeshlessField : public IndirectField {
 public:
  // `receiver_irradiance`: 9 floats per basis point (RGB channel-major vector irradiance).
  // `visibility` (optional) enables the visibility-aware evaluation; it must outlive every
  // evaluate() (the bake job's tracer does, as for antiradiance).
  MeshlessField(std::shared_ptr<const MeshlessPrecomputation> system,
                std::vector<float> receiver_irradiance, const RayTracer* visibility = nullptr)
      : system_(std::move(system)),
        irradiance_(std::move(receiver_irradiance)),
        visibility_(visibility) {}
  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override;

 private:
  std::shared_ptr<const MeshlessPrecomputation> system_;
  std::vector<float> irradiance_;
  const RayTracer* visibility_ = nullptr;
};

class MeshlessSolver : public Solver {
 public:
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;

  bool can_relight() const override { return true; }
  std::vector<std::string> relight_settings() const override {
    return {"direct_samples", "visibility"};
  }
  std::shared_ptr<const Precomputation> precomputation() const override { return precomputation_; }
  std::unique_ptr<IndirectField> relight(const SolveInputs& inputs, const Precomputation& reuse,
                                         JobContext& context) override;

 private:
  std::shared_ptr<const MeshlessPrecomputation> precompute(const SolveInputs& inputs,
                                                           JobContext& context) const;
  std::unique_ptr<IndirectField> light(const SolveInputs& inputs,
                                       std::shared_ptr<const MeshlessPrecomputation> system,
                                       JobContext& context) const;

  std::shared_ptr<const Precomputation> precomputation_;
};

}  // namespace bakegi
