// Multilevel meshless approximation (Lehtinen et al. 2008, §2.1, §2.4, §4.1): the
// coarse-to-fine projection P (Eqs. 4-7), the pull-push projection P†, evaluation of the
// expansion F_L = Σ_j α_j B_j (Eq. 6) and flattening into a single-level basis for display.
//
// Values carry `channels` floats per point (1: scalar irradiance, 3: RGB, 9: RGB irradiance
// vectors), stored flat: value c of point j at [j * channels + c], points in
// BasisHierarchy order (sorted by level, see BasisHierarchy::input_index).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/meshless/basis_hierarchy.h"

namespace bakegi {
class JobContext;
}

namespace bakegi::meshless {

// P: α from samples f_j = f(p_j) at every point of every level, coarse to fine:
// α_j = f_j - F_{l-1}(p_j) (Eq. 7), F_{-1} = 0. Where no coarser level covers p_j, the
// coarser approximation there is 0 and α_j = f_j. `job` (optional) is checked for cancel
// between levels.
std::vector<float> project_samples(const BasisHierarchy& basis, std::span<const float> samples,
                                   uint32_t channels, const JobContext* job = nullptr);

// The pull half of P† (§2.1 "Pull-Push Approximation"): the finest level keeps its samples;
// from the second-finest level up, each point's value becomes the average of its children's
// values weighted by its own kernel, Σ_c w_i(p_c) v_c / Σ_c w_i(p_c): a discrete estimate of
// ∫ w_i f / ∫ w_i, the local mean under the point's own support, independent of how its
// level's neighbors share that region (B_i(p_c) would tie it to them). Points without
// children keep their own sample.
std::vector<float> pull_averages(const BasisHierarchy& basis, std::span<const float> samples,
                                 uint32_t channels, const JobContext* job = nullptr);

// P†: pull_averages, then the coarse-to-fine pass of project_samples with those averages as
// the f_j. Coarse coefficients carry local means, finer ones deviations from them.
std::vector<float> pull_push_project(const BasisHierarchy& basis, std::span<const float> samples,
                                     uint32_t channels, const JobContext* job = nullptr);

// Eq. 6 at one query (x, n): out[c] = Σ_levels Σ_j α_j B_j(x, n), each level normalized on
// its own and skipped where it does not cover (x, n). `scratch` is reused between calls.
// Returns false (and zeros in out) where no level covers (x, n).
bool evaluate(const BasisHierarchy& basis, std::span<const float> coefficients, uint32_t channels,
              const glm::vec3& x, const glm::vec3& n, std::span<float> out,
              std::vector<BasisValue>& scratch);

// evaluate for a batch: out holds positions.size() * channels floats. Parallel (TBB) and
// deterministic: every query is computed the same way whatever the thread count. Returns
// how many queries no level covered (their values are 0).
size_t evaluate_many(const BasisHierarchy& basis, std::span<const float> coefficients,
                     uint32_t channels, std::span<const glm::vec3> positions,
                     std::span<const glm::vec3> normals, std::span<float> out,
                     const JobContext* job = nullptr);

// Which points, with which radii, make the single level of a flattened basis (§4.1: "a
// single-level meshless basis constructed from the same points").
enum class FlatPoints {
  // The finest level's points and radii, plus every coarser point (own radius) whose
  // position the finest level does not cover, so holes of the finest level stay covered
  // (at a single coarse level's accuracy there: a Shepard level smooths at its own scale).
  // The most accurate choice measured (test FlatteningMatchesHierarchicalEvaluation): the
  // finest level is the densest quasi-uniform set, and Shepard bias grows with density
  // changes. Coverage is exact at every hierarchy point; a query in a hole of the finest
  // level that only coarse points placed where the finest level does reach could cover may
  // be left uncovered (evaluate_many counts those).
  kFinestLevel,
  // Every point with the finest level's (largest) radius: as dense as the finest level
  // plus 1/3 from the coarser ones, but the extra points are irregular, which biases the
  // Shepard average (measured ~1.3x the error of kFinestLevel).
  kAllPointsFinestRadius,
  // Every point with its own radius: covers everywhere the hierarchy does, but the coarse
  // points' wide kernels blur the result (measured ~6x the error of kFinestLevel).
  kAllPointsOwnRadius,
};

// A single-level basis and its coefficients; evaluate it with evaluate / evaluate_many
// like any hierarchy (one level: one R-tree query per bake point instead of L + 1).
struct FlatExpansion {
  BasisHierarchy basis;
  std::vector<float> coefficients;
  uint32_t channels = 1;
};

// Resamples F_L (given by `coefficients` on `basis`) into a single-level basis: β_i = F_L(p_i)
// at every chosen point (F_L is defined there: w_i(p_i) = 1 covers p_i on its own level),
// the flat level's Shepard coefficients. A single Shepard level smooths (its bias is
// O(r^2 ∇²F)); each correction pass adds the flat level's own residual at its points,
// β += F_L(p_i) - S β(p_i) (one more level on the same points, as in Eq. 4), which cancels
// most of that bias.
FlatExpansion flatten(const BasisHierarchy& basis, std::span<const float> coefficients,
                      uint32_t channels, FlatPoints choice = FlatPoints::kFinestLevel,
                      uint32_t correction_passes = 1, const JobContext* job = nullptr);

}  // namespace bakegi::meshless
