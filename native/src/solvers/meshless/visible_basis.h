// Visibility-aware versions of the basis' own relations, so that the coefficients of the
// meshless expansion never mix values from both sides of a wall (the leak of §5.2).
//
// Why: a basis function's support (Eq. 10) ignores occluders. Floor points on the two sides
// of a wall share their normal and are close in the 5D metric of Eq. 11, so without this
// (measured on the two-rooms scene, see docs/methods/meshless.md):
//   - the pull of P† (§2.1) averaged lit children from the other room into a coarse sender,
//   - Eq. 7 / Eq. 17 subtracted, from a fine point's sample, coarse functions it cannot see,
//   - the gathering integral (Eq. 16) gave a ray's hit point the coefficients of coarse
//     senders centred in the other room, which then carried that room's light (directly and
//     in every bounce after the first, which uses only the coarsest level).
// The rule everywhere is the one visible_evaluation.h applies at bake points: a query (x, n)
// uses, per level, only the functions whose point it sees (lifted_visibility.h, lift
// kLiftOfRadius · r_j + kLiftPerDistance · distance), renormalized within the level (Shepard);
// a level none of whose functions it sees adds nothing there.
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

// Whether (x, n) sees basis point p (the shared test of visible_evaluation.h).
bool sees_basis_point(const RayTracer& tracer, const glm::vec3& x, const glm::vec3& n,
                      const BasisPoint& p);

// Appends (j, B^vis_j(x, n)) for `level` (every function when `tracer` is null): the level's
// weights of the points (x, n) sees, renormalized. Returns the visible weight sum (0: nothing
// appended). `candidates` is scratch; `rays` counts the occlusion rays cast.
float gather_visible_basis(const BasisHierarchy& basis, const RayTracer* tracer, uint32_t level,
                           const glm::vec3& x, const glm::vec3& n, std::vector<BasisValue>& out,
                           std::vector<BasisValue>& candidates, uint64_t& rays);

// The relations P† and Eq. 7 / Eq. 17 read from the DAG, restricted to what sees what:
//   pull(i):    (child c, w_i(p_c) / Σ) over the children of i that see p_i (empty: i keeps
//               its own sample);
//   coarser(j): (k, B^vis_k(p_j)) over the coarser points k that p_j sees, renormalized per
//               level; a coarser level none of whose functions p_j sees is left out.
// Without a tracer they equal the plain DAG's (children weights, coarser_basis).
struct VisibleRelations {
  std::vector<uint64_t> pull_offsets;  // size() + 1
  std::vector<BasisValue> pull;
  std::vector<uint64_t> coarser_offsets;  // size() + 1
  std::vector<BasisValue> coarser;
  uint64_t rays = 0;
  uint64_t blocked = 0;

  std::span<const BasisValue> pull_of(uint32_t i) const {
    return {pull.data() + pull_offsets[i], pull.data() + pull_offsets[i + 1]};
  }
  std::span<const BasisValue> coarser_of(uint32_t j) const {
    return {coarser.data() + coarser_offsets[j], coarser.data() + coarser_offsets[j + 1]};
  }
  size_t memory_bytes() const {
    return (pull_offsets.capacity() + coarser_offsets.capacity()) * sizeof(uint64_t) +
           (pull.capacity() + coarser.capacity()) * sizeof(BasisValue);
  }
};

// Parallel (TBB), deterministic; `job` (optional) is checked for cancel.
VisibleRelations visible_relations(const BasisHierarchy& basis, const RayTracer* tracer,
                                   const JobContext* job = nullptr);

// P† with the relations: the pull (finest level keeps its samples, each coarser point the
// weighted mean of its visible children's pulled values), then α_j = f_j − Σ coarser(j) α_k
// (Eq. 7). Coarse coefficients carry local means of what they see, finer ones deviations.
std::vector<float> visible_pull_push_project(const BasisHierarchy& basis,
                                             const VisibleRelations& relations,
                                             std::span<const float> samples, uint32_t channels,
                                             const JobContext* job = nullptr);

}  // namespace bakegi::meshless
