// Evaluation of the expansion F_L = Σ_j α_j B_j (Eq. 6) at bake points with the basis
// functions a point cannot see left out (the leak of §5.2, handled as the antiradiance splat
// does in surface_interpolation.h).
//
// Why: a basis function's support is an ellipsoid (Eq. 10) that ignores occluders, so the
// functions of a lit floor reach under a box standing on it (the Cornell box's floor corners
// under the boxes held 35% of the squared error) and dark ones reach out. For each bake point
// and each level, every point j with w_j(x, n) > 0 is tested with one occlusion ray between
// x and x_j, both lifted off their surfaces along their normals by
// kLiftOfRadius · r_j + kLiftPerDistance · |x − x_j| (the distance part keeps the segment
// off gently curved surfaces, as in surface_interpolation.h; any occluder taller than the
// lift between the two still blocks). The visible weights are renormalized within the level,
// so each level stays a partition of unity (Shepard). A level none of whose candidates the
// point sees adds nothing: the point cannot receive what that level carries (on the Cornell
// box these are the floor corners under the boxes: every coarse function there sits on the
// lit floor outside, and using their unblocked value instead, as the antiradiance splat does
// for its single level, left those corners at 55% of the floor's mean; measured 13.5% against
// 12.4% error at levels=4). Below a level the point does see, such a level is completed
// through that level's points (level_completion.h: the coefficients the point sees are
// differences from what those points saw, so without it the bulk of the light was lost; on the
// living room's sofas about 30%). A point that sees no candidate of any level gets the unblocked
// value scaled by its openness: the fraction of 16 cosine-weighted rays that travel farther
// than the smallest support radius among its candidates. In a gap narrower than the basis
// (1 cm behind a bookshelf standing off a wall, under a board resting on another) that is
// about 0: the unblocked value alone carried the lit side's light through the surface, and
// on the office the bookshelf's back and sides held 88% of the weighted squared error. On an
// open but finely detailed surface (the cushions of a sofa, whose basis centres the lifted
// segments fail to reach) it is about 1: 0 there lost the light of 2,336 points of a living
// room that the reference has at 1.9x the mean.
//
// The coefficients α were computed (Eq. 7, Eq. 17) with unblocked basis functions; leaving
// functions out at evaluation changes only how a level's coefficients are interpolated, not
// what they are.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/meshless/basis_hierarchy.h"

namespace bakegi {
class JobContext;
class RayTracer;
}  // namespace bakegi

namespace bakegi::meshless {

struct VisibleRelations;

inline constexpr float kLiftOfRadius = 0.01f;     // of the basis function's radius r_j
inline constexpr float kLiftPerDistance = 0.15f;  // of the point-to-center distance

struct VisibleEvaluationStats {
  uint64_t rays = 0;
  uint64_t blocked = 0;           // candidates left out
  uint64_t levels_skipped = 0;    // (point, level) pairs left out: every candidate blocked
  uint64_t points_blind = 0;      // points that see no candidate at all (openness-scaled)
  uint64_t levels_completed = 0;  // skipped levels completed through finer ones
  size_t uncovered = 0;           // queries no level covers (their values are 0)
};

// The expansion at a fixed set of points is linear in the coefficients: row q holds
// (j, weight of α_j at point q), so evaluating it again (a relight) is one sparse product
// instead of R-tree queries and visibility rays.
struct EvaluationWeights {
  std::vector<uint64_t> offsets;    // points + 1: row q is entries[offsets[q], offsets[q + 1])
  std::vector<BasisValue> entries;  // (basis point, weight)

  size_t point_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  size_t memory_bytes() const {
    return offsets.capacity() * sizeof(uint64_t) + entries.capacity() * sizeof(BasisValue);
  }
  // out[q * channels + c] = Σ weight · coefficients[j * channels + c]. Parallel, deterministic.
  void apply(std::span<const float> coefficients, uint32_t channels, std::span<float> out) const;
};

// The weights of the points under the rule above: with `tracer`, the visibility test; without,
// plain per-level Shepard weights (as evaluate_many). With `completion` (the coarser
// relations the coefficients were computed with), a skipped level below a level the point
// sees is completed through that level's points (level_completion.h). Parallel (TBB) and
// deterministic; `job` (optional) is checked for cancel and gets stage progress.
VisibleEvaluationStats visible_weights(const BasisHierarchy& basis, const RayTracer* tracer,
                                       std::span<const glm::vec3> positions,
                                       std::span<const glm::vec3> normals,
                                       EvaluationWeights& weights, JobContext* job = nullptr,
                                       const VisibleRelations* completion = nullptr);

// Like evaluate_many (multilevel_approximation.h), with the visibility test. Parallel (TBB)
// and deterministic (each query depends only on itself); `job` (optional) is checked for
// cancel between blocks of queries and gets stage progress.
VisibleEvaluationStats evaluate_visible_many(const BasisHierarchy& basis,
                                             std::span<const float> coefficients, uint32_t channels,
                                             const RayTracer& tracer,
                                             std::span<const glm::vec3> positions,
                                             std::span<const glm::vec3> normals,
                                             std::span<float> out, JobContext* job = nullptr);

}  // namespace bakegi::meshless
