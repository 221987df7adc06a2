// What the meshless solver precomputes from geometry, materials and settings alone (Lehtinen
// et al. 2008, §2-3.2): the basis, its sender part and S = T + T² + …, with the statistics a
// bake reports about them. Relighting reuses it in memory (MeshlessSolver::relight) and the
// precomputation cache (precomputation_cache.h) saves and reloads it across sessions.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/multi_bounce.h"
#include "solvers/meshless/visible_basis.h"
#include "solvers/meshless/visible_evaluation.h"
#include "solvers/solver.h"

namespace bakegi {

// What a bake reports about the precomputation, kept with it so that a
// bake that loads it from the cache reports the same as the bake that made it.
struct MeshlessStatistics {
  uint32_t sender_levels = 0;
  std::vector<uint64_t> receivers_per_level;  // receivers whose links were computed
  std::vector<uint64_t> links_per_level;      // links kept, by receiver level
  uint64_t links = 0;
  uint64_t potential_links = 0;
  int32_t refinement_stopped_at_level = -1;  // >= 0: the memory budget stopped refinement
  bool levels_reduced = false;               // the memory budget lowered the automatic levels
  uint32_t bounces = 1;
  std::vector<double> bounce_fractions;
  double coarse_spacing = 0.0;  // metres, level 0
  double mean_free_path = 0.0;  // metres, the pilot's (what the automatic spacing follows)
  uint64_t link_bytes = 0;      // the single-bounce operator T while it existed
  uint64_t placement_rays = 0;  // rays the precomputation cast (a cache hit casts none)
  uint64_t refinement_rays = 0;
  double precompute_seconds = 0.0;  // placement + basis + refinement + bounces
};

// What relighting reuses: the basis, the sender basis and S (geometry, materials, settings).
struct MeshlessPrecomputation : Precomputation,
                                std::enable_shared_from_this<MeshlessPrecomputation> {
  explicit MeshlessPrecomputation(meshless::BasisHierarchy all_in,
                                  meshless::BasisHierarchy senders_in)
      : all(std::move(all_in)), senders(std::move(senders_in)) {}
  meshless::BasisHierarchy all;      // every receiver level
  meshless::BasisHierarchy senders;  // the first sender levels of the same points (same indices)
  meshless::DirectToIndirect transfer;
  // Per sender: the cosine-weighted fraction of its hemisphere open to the world
  // (sky_visibility.h), so that the world's direct light is exact for any world colour.
  std::vector<float> sender_sky_visibility;
  // The coarser relations of `all` that Eq. 17 used (visible_basis.h, the pull part empty):
  // bake points complete the levels they cannot see with them (level_completion.h). Null
  // without the visibility test.
  std::shared_ptr<const meshless::VisibleRelations> receiver_relations;
  MeshlessStatistics statistics;

  // The evaluation weights of the last bake points evaluated, so that relighting the same
  // points is one sparse product (no R-tree queries, no visibility rays). Keyed by a hash of
  // the points and the visibility flag.
  std::shared_ptr<const meshless::EvaluationWeights> weights_for(uint64_t key) const {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    return key == weights_key_ ? weights_ : nullptr;
  }
  void keep_weights(uint64_t key,
                    std::shared_ptr<const meshless::EvaluationWeights> weights) const {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    weights_key_ = key;
    weights_ = std::move(weights);
  }

  // The sender basis's relations for P† (visible_basis.h). They depend on geometry alone, so
  // the first lighting makes them and every relight reuses them (on Sponza they cost more
  // than the rest of a relight). `tracer` null: the relations without visibility.
  std::shared_ptr<const meshless::VisibleRelations> sender_relations(const RayTracer* tracer,
                                                                     const JobContext* job) const {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    const bool visible = tracer != nullptr;
    if (!relations_ || relations_visible_ != visible) {
      relations_ = std::make_shared<const meshless::VisibleRelations>(
          meshless::visible_relations(senders, tracer, job));
      relations_visible_ = visible;
    }
    return relations_;
  }

  size_t memory_bytes() const override {
    std::lock_guard<std::mutex> lock(weights_mutex_);
    return all.memory_bytes() + senders.memory_bytes() + transfer.memory_bytes() +
           sender_sky_visibility.size() * sizeof(float) +
           (receiver_relations ? receiver_relations->memory_bytes() : 0) +
           (weights_ ? weights_->memory_bytes() : 0) +
           (relations_ ? relations_->memory_bytes() : 0);
  }

 private:
  mutable std::shared_ptr<const meshless::VisibleRelations> relations_;
  mutable bool relations_visible_ = false;
  mutable std::mutex weights_mutex_;
  mutable std::shared_ptr<const meshless::EvaluationWeights> weights_;
  mutable uint64_t weights_key_ = 0;
};

}  // namespace bakegi
