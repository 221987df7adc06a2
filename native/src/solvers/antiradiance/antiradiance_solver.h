// The Antiradiance solver ("antiradiance", Dachsbacher et al. 2007): indirect light without
// visibility rays. solve() builds the whole solution (bins, element hierarchy, links, direct
// light at the patches, iteration); relight() reuses the first three; the returned field only
// interpolates the patches' indirect irradiance at the bake points (surface_interpolation.h), so
// evaluation is cheap.
//
// Settings (read with ranges; a bad value fails before any work):
//   bins            directional bins, 12..3072 (default 300; rounded to a HEALPix count)
//   iterations      bounces at most, 1..100000 (default 32)
//   tolerance       stop when an iteration adds less than this fraction, 0..1 (default 1e-4)
//   scheme          "symmetric" (default) or "asymmetric" (§2.2)
//   patch_size      largest patch edge in metres, 0 = automatic (default 0)
//   direct_samples  direct-light samples per patch, 1..65536 (default 64)
//   seed            random stream of the direct-light samples (default 0)
//   memory_budget_mb  the job's budget; hierarchy, bin tables and links must fit in what the
//                   ray tracer leaves of it
// Automatic patch size: the scene's default (extent / 16), coarsened by factors of 2 until
// the estimate fits the budget, with a warning whenever it coarsens. A requested patch size
// that does not fit is refused, naming one that would.
#pragma once

#include <memory>

#include "solvers/antiradiance/near_field_gather.h"
#include "solvers/antiradiance/surface_interpolation.h"
#include "solvers/solver.h"

namespace bakegi {

class AntiradianceField : public IndirectField {
 public:
  explicit AntiradianceField(antiradiance::SurfaceInterpolation interpolation,
                             antiradiance::NearFieldGather near_field = {})
      : interpolation_(std::move(interpolation)), near_field_(std::move(near_field)) {}
  // Parallel over points, cancellable.
  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override;

  const antiradiance::SurfaceInterpolation& interpolation() const { return interpolation_; }

 private:
  antiradiance::SurfaceInterpolation interpolation_;
  antiradiance::NearFieldGather near_field_;
};

struct AntiradiancePrecomputation;

class AntiradianceSolver : public Solver {
 public:
  std::unique_ptr<IndirectField> solve(const SolveInputs& inputs, JobContext& context) override;

  // Relighting without relinking (§3.3): bins, hierarchy and links stay; direct light is
  // initialized anew from inputs.scene's lights and the iteration runs again.
  bool can_relight() const override { return true; }
  std::vector<std::string> relight_settings() const override {
    return {"iterations", "tolerance", "scheme", "direct_samples", "seed"};
  }
  std::shared_ptr<const Precomputation> precomputation() const override { return precomputation_; }
  std::unique_ptr<IndirectField> relight(const SolveInputs& inputs, const Precomputation& reuse,
                                         JobContext& context) override;

 private:
  // Bins, spreading tables, hierarchy (patch size from the budget) and links.
  std::shared_ptr<const AntiradiancePrecomputation> prepare(const SolveInputs& inputs,
                                                            JobContext& context);
  // Bin tables, direct light, iteration and the output field.
  std::unique_ptr<IndirectField> light(const SolveInputs& inputs,
                                       const AntiradiancePrecomputation& system,
                                       JobContext& context) const;

  std::shared_ptr<const Precomputation> precomputation_;
};

}  // namespace bakegi
