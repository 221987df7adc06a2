#include "solvers/meshless/multi_bounce.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::meshless {

namespace {

SparseOperator single_bounce(const TransferOperator& op, int channel) {
  std::vector<Eigen::Triplet<float, int32_t>> triplets;
  triplets.reserve(op.link_count() * 3);
  for (size_t r = 0; r < op.receivers.size(); ++r) {
    for (const TransferLink& link : op.receivers[r]) {
      for (int a = 0; a < 3; ++a) {
        const float v = link.value[channel][a];
        if (v != 0.0f) triplets.emplace_back(static_cast<int32_t>(3 * r + a), link.sender, v);
      }
    }
  }
  SparseOperator t(static_cast<int32_t>(3 * op.receivers.size()),
                   static_cast<int32_t>(op.sender_count));
  t.setFromTriplets(triplets.begin(), triplets.end());
  return t;
}

}  // namespace

size_t DirectToIndirect::memory_bytes() const {
  size_t bytes = 0;
  for (const SparseOperator& m : channel) {
    bytes += static_cast<size_t>(m.nonZeros()) * (sizeof(float) + sizeof(int32_t)) +
             static_cast<size_t>(m.outerSize() + 1) * sizeof(int32_t);
  }
  return bytes;
}

size_t DirectToIndirect::nonzeros() const {
  size_t n = 0;
  for (const SparseOperator& m : channel) n += static_cast<size_t>(m.nonZeros());
  return n;
}

namespace {

// v (3 per coarsest receiver, one channel) -> s_k = n_k · v_k.
void to_scalar(const BasisHierarchy& basis, int32_t coarsest, const std::vector<double>& v,
               std::vector<double>& s) {
  s.assign(static_cast<size_t>(coarsest), 0.0);
  for (int32_t k = 0; k < coarsest; ++k) {
    const glm::vec3 n = basis.point(static_cast<uint32_t>(k)).normal;
    s[k] = n.x * v[3 * k] + n.y * v[3 * k + 1] + n.z * v[3 * k + 2];
  }
}

// v = T_00 s: the coarsest receivers' vector irradiance from the coarsest senders' scalars.
void coarsest_hop(const SparseOperator& t, int32_t coarsest, const std::vector<double>& s,
                  std::vector<double>& v) {
  v.assign(3 * static_cast<size_t>(coarsest), 0.0);
  for (int32_t k = 0; k < coarsest; ++k) {
    if (s[k] == 0.0) continue;
    for (SparseOperator::InnerIterator it(t, k); it && it.row() < 3 * coarsest; ++it) {
      v[it.row()] += double(it.value()) * s[k];
    }
  }
}

double absolute_sum(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += std::abs(x);
  return sum;
}

}  // namespace

DirectToIndirect solve_bounces(const BasisHierarchy& all, const TransferOperator& op,
                               const BounceSettings& settings, JobContext& context,
                               BounceStats& stats) {
  if (op.receivers.size() != all.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless bounces: operator and basis disagree");
  }
  const int32_t coarsest = static_cast<int32_t>(all.level_end(0));
  if (coarsest > static_cast<int32_t>(op.sender_count)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless bounces: the coarsest level must be among the senders");
  }
  DirectToIndirect s;
  stats = BounceStats{};
  for (int c = 0; c < 3; ++c) {
    context.throw_if_cancelled();
    s.channel[c] = single_bounce(op, c);
    s.channel[c].makeCompressed();
    context.set_stage_progress((c + 1) / 3.0);
  }
  // Statistics: the series for unit emission at every sender (green).
  const SparseOperator& t = s.channel[1];
  std::vector<double> v(3 * static_cast<size_t>(coarsest), 0.0), scalar;
  for (int32_t j = 0; j < t.outerSize(); ++j) {
    for (SparseOperator::InnerIterator it(t, j); it && it.row() < 3 * coarsest; ++it) {
      v[it.row()] += it.value();
    }
  }
  to_scalar(all, coarsest, v, scalar);
  const double first = std::max(absolute_sum(scalar), 1e-30);
  while (stats.bounces < settings.max_bounces) {
    coarsest_hop(t, coarsest, scalar, v);
    to_scalar(all, coarsest, v, scalar);
    ++stats.bounces;
    const double fraction = absolute_sum(scalar) / first;
    stats.bounce_fraction.push_back(fraction);
    if (fraction < settings.tolerance) break;
  }
  stats.nonzeros = s.nonzeros();
  return s;
}

void apply_operator(const DirectToIndirect& s, const BasisHierarchy& basis, uint32_t max_bounces,
                    float tolerance, const std::vector<float>& e, float skip,
                    std::vector<float>& i) {
  const int32_t rows = s.channel[0].rows();
  if (static_cast<size_t>(rows) != 3 * basis.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless apply: operator and basis disagree");
  }
  i.assign(static_cast<size_t>(rows) * 3, 0.0f);  // rows = 3 receivers -> 9 floats each
  const int32_t coarsest =
      std::min<int32_t>(static_cast<int32_t>(basis.level_end(0)), s.channel[0].cols());
  std::vector<double> v, scalar, total;
  for (int c = 0; c < 3; ++c) {
    const SparseOperator& m = s.channel[c];
    // First bounce, T e.
    for (int32_t j = 0; j < m.outerSize(); ++j) {
      const float ej = e[3 * static_cast<size_t>(j) + c];
      if (!(std::abs(ej) > skip)) continue;
      for (SparseOperator::InnerIterator it(m, j); it; ++it) {
        const int32_t row = it.row();
        const int32_t receiver = row / 3, axis = row % 3;
        i[9 * static_cast<size_t>(receiver) + 3 * c + axis] += it.value() * ej;
      }
    }
    if (max_bounces < 2 || coarsest == 0) continue;
    // s = Σ_{k=0}^{B-2} N^k D T_0 e on the coarsest block.
    v.assign(3 * static_cast<size_t>(coarsest), 0.0);
    for (int32_t k = 0; k < coarsest; ++k) {
      for (int a = 0; a < 3; ++a) v[3 * k + a] = i[9 * static_cast<size_t>(k) + 3 * c + a];
    }
    to_scalar(basis, coarsest, v, scalar);
    total = scalar;
    const double first = absolute_sum(scalar);
    for (uint32_t bounce = 3; bounce <= max_bounces && first > 0.0; ++bounce) {
      coarsest_hop(m, coarsest, scalar, v);
      to_scalar(basis, coarsest, v, scalar);
      for (int32_t k = 0; k < coarsest; ++k) total[k] += scalar[k];
      if (absolute_sum(scalar) < double(tolerance) * first) break;
    }
    // The last hop to every receiver: i += T_{·0} s.
    for (int32_t k = 0; k < coarsest; ++k) {
      const double sk = total[k];
      if (!(std::abs(sk) > skip)) continue;
      for (SparseOperator::InnerIterator it(m, k); it; ++it) {
        const int32_t row = it.row();
        const int32_t receiver = row / 3, axis = row % 3;
        i[9 * static_cast<size_t>(receiver) + 3 * c + axis] += float(double(it.value()) * sk);
      }
    }
  }
}

}  // namespace bakegi::meshless
