// The meshless hierarchical basis (Lehtinen et al. 2008, §2.1-2.2): points on levels
// 0 (coarsest) .. L, each with a weight function (weight_function.h); the basis functions of
// a level are the Shepard-normalized weights of that level's points (Eq. 2). One spatial
// index per level (an R-tree, as in the paper) finds every function that is non-zero at a
// query, and the neighbor / parent / child DAG is stored flat.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/meshless/weight_function.h"

namespace bakegi {
class JobContext;
}

namespace bakegi::meshless {

struct BasisValue {
  uint32_t index;  // point index in BasisHierarchy::points()
  float value;     // w_j(x, n) or B_j(x, n), whichever the call says
};

class BasisHierarchy {
 public:
  // Sorts the points by level (stable) and builds the indices and the DAG. Levels must be
  // contiguous from 0; radii positive; normals unit. Throws Error(INVALID_ARGUMENT) otherwise.
  // `job` (optional) is checked for cancel during the DAG build (parallel, TBB).
  explicit BasisHierarchy(std::vector<BasisPoint> points, const JobContext* job = nullptr);
  ~BasisHierarchy();
  BasisHierarchy(BasisHierarchy&&) noexcept;
  BasisHierarchy& operator=(BasisHierarchy&&) noexcept;

  size_t size() const;
  uint32_t level_count() const;
  std::span<const BasisPoint> points() const;
  const BasisPoint& point(uint32_t index) const;
  // The position of points()[index] in the vector given to the constructor (the sort by
  // level is stable, so this is increasing within a level).
  uint32_t input_index(uint32_t index) const;
  // Points of level l are [level_begin(l), level_end(l)).
  uint32_t level_begin(uint32_t level) const;
  uint32_t level_end(uint32_t level) const;

  // Appends (j, w_j(x, n)) for every point j of `level` whose weight is > 0 at (x, n), in
  // the level's R-tree order (fixed for a given hierarchy). Thread-safe (const queries).
  void gather_weights(uint32_t level, const glm::vec3& x, const glm::vec3& n,
                      std::vector<BasisValue>& out) const;
  // Appends (j, B_j(x, n)) for `level` (Eq. 2, normalized within the level); appends nothing
  // where the level does not cover (x, n). Returns the weight sum. Appended in increasing j.
  float gather_basis(uint32_t level, const glm::vec3& x, const glm::vec3& n,
                     std::vector<BasisValue>& out) const;

  // The DAG of §2.1, for point j on level l:
  //   neighbors(j): points n != j of level l with B_j(p_n) != 0;
  //   children(j):  points of level l+1 with B_j(p_c) != 0;
  //   parents(j):   points k of level l-1 with B_k(p_j) != 0.
  std::span<const uint32_t> neighbors(uint32_t index) const;
  std::span<const uint32_t> children(uint32_t index) const;
  std::span<const uint32_t> parents(uint32_t index) const;
  // (k, B_k(p_j)) for every point k on every level coarser than j's with B_k(p_j) != 0:
  // what F_{l-1}(p_j) (Eq. 7) and the differencing of Eq. 17 ("all-parents") sum over.
  std::span<const BasisValue> coarser_basis(uint32_t index) const;

  size_t memory_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bakegi::meshless
