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
//   sender_levels   sender levels (the first ones), 0 = automatic: all receiver levels but the
//                   finest (the paper: 6 receiver / 3 sender levels; Cornell 5.2% -> 4.6%)
//   epsilon         the link threshold ε in the paper's units (default 0.01; the paper's 0.025
//                   drops links that carry energy here: Cornell 7.8% -> 6.3% at 0.01)
//   gather_rays     hemisphere rays per receiver of Eq. 16 (default 256)
//   bounces         bounces at most, the first included (default 16; the paper simulated 4)
//   direct_samples  direct-light samples per sender point (default 4: P† averages them over
//                   the sender basis; Cornell 4.62% at 16, 4.71% at 4, Sponza relight 2x faster)
//   sender_cutoff   lighting skips senders whose coefficient is below this fraction of the
//                   largest (§3.3 "skipping senders below ε"; default 1e-3, 0 = none)
//   viewpoint       "x,y,z": importance particles start there (§2.3); empty (default): they
//                   leave the bake points, which define the surfaces that matter for a bake
//   visibility      1 (default): at bake points, leave out basis functions whose point the
//                   bake point cannot see (visible_evaluation.h); 0: plain Eq. 6
//   seed, memory_budget_mb
//   cache_dir       a folder (UTF-8): solve() saves the precomputation there and a later solve
//                   of the same scene and settings loads it instead of precomputing
//                   (precomputation_cache.h: keyed by geometry, materials, the settings that
//                   shape it and the bake points that placed it; a stale or corrupt file is
//                   rebuilt with a warning, an unwritable folder is a warning). Empty
//                   (default): no cache. The report says "meshless_cache": hit, miss, stale
//                   or off, with "meshless_cache_path", the load/save seconds and the bytes.
#pragma once

#include <memory>
#include <span>
#include <string>
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
  // Not "visibility": the gather's visibility test (gather_integral.h) shapes T, so a relight
  // or a cache hit with another value would reuse links made under the other rule.
  // "bounces": the series runs when lighting (apply_operator); only the reported bounce
  // statistics of the precomputation used it.
  std::vector<std::string> relight_settings() const override {
    return {"direct_samples", "sender_cutoff", "bounces", "cache_dir"};
  }
  std::shared_ptr<const Precomputation> precomputation() const override { return precomputation_; }
  std::unique_ptr<IndirectField> relight(const SolveInputs& inputs, const Precomputation& reuse,
                                         JobContext& context) override;

 private:
  std::shared_ptr<const MeshlessPrecomputation> precompute(const SolveInputs& inputs,
                                                           JobContext& context) const;
  // precompute() through the cache in `cache_dir` (precomputation_cache.h): loads a file made
  // for the same scene and settings, else precomputes and saves.
  std::shared_ptr<const MeshlessPrecomputation> load_or_precompute(const SolveInputs& inputs,
                                                                   const std::string& cache_dir,
                                                                   JobContext& context) const;
  std::unique_ptr<IndirectField> light(const SolveInputs& inputs,
                                       std::shared_ptr<const MeshlessPrecomputation> system,
                                       JobContext& context) const;

  std::shared_ptr<const Precomputation> precomputation_;
};

}  // namespace bakegi
