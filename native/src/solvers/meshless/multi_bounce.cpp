#include "solvers/meshless/multi_bounce.h"

#include <cmath>

#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::meshless {

namespace {

double absolute_sum(const SparseOperator& m) {
  double sum = 0.0;
  for (int k = 0; k < m.outerSize(); ++k) {
    for (SparseOperator::InnerIterator it(m, k); it; ++it) sum += std::abs(it.value());
  }
  return sum;
}

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
  // D: scalar irradiance n_k · E_k of coarsest sender k from coarsest receiver k's vector.
  std::vector<Eigen::Triplet<float, int32_t>> dot_triplets;
  for (int32_t k = 0; k < coarsest; ++k) {
    const glm::vec3 n = all.point(static_cast<uint32_t>(k)).normal;
    for (int a = 0; a < 3; ++a) dot_triplets.emplace_back(k, 3 * k + a, n[a]);
  }
  SparseOperator to_scalar(coarsest, 3 * coarsest);
  to_scalar.setFromTriplets(dot_triplets.begin(), dot_triplets.end());

  DirectToIndirect s;
  stats = BounceStats{};
  for (int c = 0; c < 3; ++c) {
    context.throw_if_cancelled();
    SparseOperator t = single_bounce(op, c);
    const SparseOperator t0 = t.topRows(3 * coarsest);
    const SparseOperator t00 = t0.leftCols(coarsest);
    const SparseOperator m = t00 * to_scalar;
    const double first = std::max(absolute_sum(t0), 1e-30);
    SparseOperator extra(3 * coarsest, t.cols());
    SparseOperator bounce = t0;
    uint32_t bounces = 1;
    std::vector<double> fractions;
    while (bounces < settings.max_bounces) {
      context.throw_if_cancelled();
      bounce = (m * bounce).pruned(settings.truncation, 1.0f);
      ++bounces;
      const double fraction = absolute_sum(bounce) / first;
      fractions.push_back(fraction);
      extra += bounce;
      if (fraction < settings.tolerance) break;
    }
    extra.conservativeResize(t.rows(), t.cols());
    s.channel[c] = t + extra;
    s.channel[c].makeCompressed();
    stats.bounces = std::max(stats.bounces, bounces);
    if (c == 1) stats.bounce_fraction = fractions;  // green: the eye's channel, for the report
    context.set_stage_progress((c + 1) / 3.0);
  }
  stats.nonzeros = s.nonzeros();
  return s;
}

void apply_operator(const DirectToIndirect& s, const std::vector<float>& e, float skip,
                    std::vector<float>& i) {
  const int32_t rows = s.channel[0].rows();
  i.assign(static_cast<size_t>(rows) * 3, 0.0f);  // rows = 3 receivers -> 9 floats each
  for (int c = 0; c < 3; ++c) {
    const SparseOperator& m = s.channel[c];
    for (int32_t j = 0; j < m.outerSize(); ++j) {
      const float ej = e[3 * static_cast<size_t>(j) + c];
      if (!(std::abs(ej) > skip)) continue;
      for (SparseOperator::InnerIterator it(m, j); it; ++it) {
        const int32_t row = it.row();
        const int32_t receiver = row / 3, axis = row % 3;
        i[9 * static_cast<size_t>(receiver) + 3 * c + axis] += it.value() * ej;
      }
    }
  }
}

}  // namespace bakegi::meshless
