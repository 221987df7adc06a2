// The adaptive hierarchical computation of the single-bounce operator T (Lehtinen et al.
// 2008, §3.2 and Fig. 5), receiver-centric: starting from every coarsest receiver, the links
// from all senders to one receiver come from one gathering integral (Eq. 16, gather_integral.h)
// minus what its coarser receivers already carry (Eq. 17):
//
//   T_ij = T'_ij - Σ_{k ∈ all-parents(i)} T_kj B_k(x_i)
//
// A link is kept when ||T_ij|| > ε and, for a sender below the coarsest level, when it also
// differs from the links of the sender's neighbours by more than ε (Appendix A: fine senders
// carry differences to local averages, so similar neighbouring links cancel). A receiver that
// keeps any link sends its children down. Levels are processed one at a time (the paper's
// queue visits them in that order too), the receivers of a level in parallel: each receiver
// depends only on its own rays and on coarser levels, so the result does not depend on the
// thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/gather_integral.h"
#include "solvers/meshless/transfer_links.h"
#include "solvers/meshless/visible_basis.h"

namespace bakegi {
struct Scene;
class RayTracer;
class JobContext;
}  // namespace bakegi

namespace bakegi::meshless {

struct RefinementSettings {
  // The paper's link threshold (all its scenes), in its units: compared with π ||T_ij||.
  float epsilon = 0.025f;
  GatherSettings gather;
  // Links may use at most this many bytes (0 = no limit): before a level is refined its links
  // are estimated from the previous level's density, and refinement stops (with a warning in
  // the stats) where the next level would not fit.
  size_t link_budget_bytes = 0;
};

struct RefinementStats {
  std::vector<uint64_t> receivers_per_level;  // receivers whose links were computed
  std::vector<uint64_t> links_per_level;      // links kept, by receiver level
  uint64_t rays = 0;                          // hemisphere rays of Eq. 16
  uint64_t visibility_rays = 0;  // occlusion rays of the visibility-aware basis (visible_basis.h)
  uint64_t hits_completed = 0;   // gather hits with a sender level completed (level_completion.h)
  uint64_t links = 0;
  uint64_t potential_links = 0;  // all receivers x all senders (Table 1's denominator)
  int stopped_at_level = -1;     // >= 0 when the budget stopped refinement before this level
};

// `all` holds every receiver level; `senders` the first levels of the same points (indices
// [0, senders.size()) agree). Cancellable; reports progress of the stage.
// `receiver_relations` (optional) gets the coarser relations of `all` that Eq. 17 used (the
// pull part empty), for completing blind levels at bake points (level_completion.h).
TransferOperator refine_transfer(const Scene& scene, const RayTracer& tracer,
                                 const BasisHierarchy& all, const BasisHierarchy& senders,
                                 const RefinementSettings& settings, JobContext& context,
                                 RefinementStats& stats,
                                 VisibleRelations* receiver_relations = nullptr);

}  // namespace bakegi::meshless
