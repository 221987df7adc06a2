// From the single-bounce operator T to the direct-to-indirect operator S = T + T² + T³ + …
// (Lehtinen et al. 2008, §3.1 Eq. 15 and end of §3.2), by sparse products (Eigen). As in the
// paper the second and later bounces use only the coarsest functions as receivers (indirect
// light after one bounce is smooth), and entries below a threshold are truncated after every
// product to keep S sparse.
//
// The coarsest receivers hold vector irradiance; to send it on, each becomes the scalar
// irradiance of the coarsest sender at the same point, n_k · E_k (the coarsest levels of
// senders and receivers are the same points). With T_0 the coarsest receivers' rows of T and
// T_00 its coarsest-sender columns, D that dot product and M = T_00 D:
//
//   S = T + [M + M² + …] T_0 (the bracket's rows padded to all receivers)
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
  std::array<SparseOperator, 3> channel;  // S for red, green, blue
  size_t memory_bytes() const;
  size_t nonzeros() const;
};

struct BounceSettings {
  uint32_t max_bounces = 16;  // total, the first included (the paper used 4)
  float tolerance = 1e-3f;    // stop when a bounce adds less than this fraction of T_0's sum
  float truncation = 0.0f;    // entries below this are dropped after every product
};

struct BounceStats {
  uint32_t bounces = 1;
  uint64_t nonzeros = 0;
  std::vector<double> bounce_fraction;  // |M^k T_0| / |T_0| per extra bounce (sums of |entries|)
};

DirectToIndirect solve_bounces(const BasisHierarchy& all, const TransferOperator& op,
                               const BounceSettings& settings, JobContext& context,
                               BounceStats& stats);

// i = S e per channel, skipping senders whose coefficient is at most `skip` in magnitude
// (§3.3: "all emitters for which e_j > ε"). e: 3 floats (RGB) per sender; i: 9 floats per
// receiver (channel-major: i[9 r + 3 c + a]).
void apply_operator(const DirectToIndirect& s, const std::vector<float>& e, float skip,
                    std::vector<float>& i);

}  // namespace bakegi::meshless
