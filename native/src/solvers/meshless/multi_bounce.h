// From the single-bounce operator T to the indirect light of all bounces, S e = (T + T² + …) e
// (Lehtinen et al. 2008, §3.1 Eq. 15 and end of §3.2). As in the paper the bounces after the
// first travel through the coarsest functions only (indirect light after one bounce is
// smooth): the coarsest receivers hold vector irradiance; to send it on, each becomes the
// scalar irradiance of the coarsest sender at the same point, n_k · E_k (the coarsest levels
// of senders and receivers are the same points). With T_0 the coarsest receivers' rows of T,
// T_00 its coarsest-sender columns, D that dot product and N = D T_00:
//
//   s = Σ_{k=0}^{B-2} N^k D T_0 e     (scalar irradiance of bounces 1..B-1 at the coarsest)
//   i = T e + T_{·0} s                (T_{·0}: every receiver's links from coarsest senders)
//
// Departure from the paper (which forms S = T + T² + … as a matrix with only coarsest
// receivers for T² onwards): the last hop of bounces 2+ lands on every receiver level, each
// finer receiver adding its own Eq. 17 differences from the coarsest senders, so bounced light
// gets the finer receivers' detail (contact shadows under objects, corners). And the series
// runs at lighting time on the small coarsest block (B-2 sparse products with T_00, then one
// with T_{·0}) instead of being stored: the stored S of the paper's form held 3 × coarsest
// rows × all senders of nearly dense bounce entries (the largest part of S on large scenes).
// So DirectToIndirect holds T only. Measured on the Cornell box: the second bounce's error
// 11.6% -> 9.7% of that bounce, all bounces 6.2% -> 5.2% (docs/methods/meshless.md).
//
// Colour channels are separate matrices (albedo differs per channel).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/transfer_links.h"

namespace bakegi {
class JobContext;
}

namespace bakegi::meshless {

// Row 3 i + a: axis a of receiver i's vector irradiance; column j: sender j. Column-major, so
// one sender's links are contiguous (the runtime walks senders, §3.3).
using SparseOperator = Eigen::SparseMatrix<float, Eigen::ColMajor, int32_t>;

struct DirectToIndirect {
  std::array<SparseOperator, 3> channel;  // T for red, green, blue (bounces: apply_operator)
  size_t memory_bytes() const;
  size_t nonzeros() const;
};

struct BounceSettings {
  uint32_t max_bounces = 16;  // total, the first included (the paper used 4)
  float tolerance = 1e-3f;    // stop when a bounce adds less than this fraction of the first
  float truncation = 0.0f;    // unused since the series runs at lighting time (apply_operator)
};

struct BounceStats {
  uint32_t bounces = 1;
  uint64_t nonzeros = 0;
  // Scalar irradiance at the coarsest points of each bounce after the first, over the first's
  // (sums), for unit emission coefficients at every sender (green channel).
  std::vector<double> bounce_fraction;
};

// Builds T per channel (the stored operator) and the bounce statistics.
DirectToIndirect solve_bounces(const BasisHierarchy& all, const TransferOperator& op,
                               const BounceSettings& settings, JobContext& context,
                               BounceStats& stats);

// i = S e per channel as in the header comment, skipping senders whose coefficient is at most
// `skip` in magnitude (§3.3: "all emitters for which e_j > ε"). e: 3 floats (RGB) per sender;
// i: 9 floats per receiver (channel-major: i[9 r + 3 c + a]). `basis`: the receiver hierarchy
// (its coarsest points are T's first columns). Bounces 2..max_bounces; the series stops
// early once a bounce adds less than `tolerance` of the first's scalar irradiance.
void apply_operator(const DirectToIndirect& s, const BasisHierarchy& basis, uint32_t max_bounces,
                    float tolerance, const std::vector<float>& e, float skip,
                    std::vector<float>& i);

}  // namespace bakegi::meshless
