// The Antiradiance solver ("antiradiance", Dachsbacher et al. 2007): indirect light without
// visibility rays. precompute() builds bins, element hierarchy and links
// (AntiradiancePrecomputation, antiradiance_precomputation.h); light() adds direct light at the
// patches and the iteration, so a relight reuses the first three; the returned field only
// interpolates the patches' indirect irradiance at the bake points (surface_interpolation.h), so
// evaluation is cheap. With "cache_dir" set the job keeps the precomputation on disk
// (codec(), precomputation_cache.h: hierarchy, links and their statistics; the bins are rebuilt)
// and a later bake of the same geometry, materials and "shapes" settings loads it instead.
//
// Settings: setting_specs() (antiradiance_method.cpp; docs/settings.md), read through
// the job's schema, so a bad value fails before any work.
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
  static const std::vector<SettingSpec>& setting_specs();

  // Relighting without relinking (§3.3): bins, hierarchy and links stay; direct light is
  // initialized anew from inputs.scene's lights and the iteration runs again.
  // Parses every antiradiance setting (a bad value fails before any work).
  void check_settings(const Settings& settings) const override;
  bool has_precomputation() const override { return true; }
  // Bins, spreading tables, hierarchy (patch size from the budget) and links; an empty scene
  // has bins only.
  std::shared_ptr<const Precomputation> precompute(const SolveInputs& inputs,
                                                   JobContext& context) override;
  // Bin tables, direct light, iteration and the output field.
  std::unique_ptr<IndirectField> light(const SolveInputs& inputs,
                                       std::shared_ptr<const Precomputation> precomputation,
                                       JobContext& context) override;
  // Hierarchy and links to and from a "cache_dir" (precomputation_cache.h).
  const PrecomputationCodec* codec() const override;
};

}  // namespace bakegi
