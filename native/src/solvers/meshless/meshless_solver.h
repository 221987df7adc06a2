// The meshless solver ("meshless", Lehtinen et al. 2008): precomputed direct-to-indirect
// transfer in a meshless hierarchical basis. solve() precomputes (point placement §2.3,
// basis §2.1-2.2, the operator T by adaptive refinement §3.2, S = T + T² + … §3.1) and then
// lights (§3.3); a relight reuses the precomputation and only lights: direct light at the
// sender points, e = P† E, i = S e. The field evaluates the indirect vector irradiance i at
// bake points through the basis (Eq. 6) and dots it with their normals.
//
// Settings: setting_specs() (meshless_method.cpp; docs/settings.md), read through the
// job's schema, so a bad value fails before any work. cache_dir: the job saves the
// precomputation there and a later bake of the same scene and settings loads it
// (bake/precomputation_store.h: keyed by geometry, materials, the settings whose role is
// "shapes" and the bake points that placed it; a stale or corrupt file is rebuilt with a
// warning, an unwritable folder is a warning).
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
  static const std::vector<SettingSpec>& setting_specs();
  // Parses every meshless setting (a bad value fails before any work).
  void check_settings(const Settings& settings) const override;

  bool has_precomputation() const override { return true; }
  // Points (§2.3), basis (§2.1-2.2), T by refinement (§3.2), S = T + T² + … (§3.1).
  std::shared_ptr<const Precomputation> precompute(const SolveInputs& inputs,
                                                   JobContext& context) override;
  // Direct light at the senders, e = P† E, i = S e (§3.3).
  std::unique_ptr<IndirectField> light(const SolveInputs& inputs,
                                       std::shared_ptr<const Precomputation> precomputation,
                                       JobContext& context) override;
  // The cache payload (precomputation_cache.h).
  const PrecomputationCodec* codec() const override;
};

}  // namespace bakegi
