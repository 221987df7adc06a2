#include "solvers/meshless/multilevel_approximation.h"

#include <algorithm>
#include <atomic>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::meshless {
namespace {

void check_values(const BasisHierarchy& basis, size_t count, uint32_t channels, const char* what) {
  if (channels == 0)
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless approximation: channels must be > 0");
  if (count != basis.size() * channels)
    throw Error(
        BAKEGI_ERROR_INVALID_ARGUMENT,
        std::string("meshless approximation: ") + what + " holds " + std::to_string(count) +
            " floats, expected points x channels = " + std::to_string(basis.size() * channels));
}

void check_cancel(const JobContext* job) {
  if (job) job->throw_if_cancelled();
}

// The coarse-to-fine pass shared by P and P†: α_j = f_j - F_{l-1}(p_j) (Eq. 7), with
// F_{l-1}(p_j) = Σ_{k in coarser_basis(j)} B_k(p_j) α_k. A level only reads coarser ones,
// so its points are independent.
std::vector<float> coarse_to_fine(const BasisHierarchy& basis, std::span<const float> values,
                                  uint32_t channels, const JobContext* job) {
  std::vector<float> alpha(values.begin(), values.end());
  for (uint32_t level = 1; level < basis.level_count(); ++level) {
    check_cancel(job);
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(basis.level_begin(level), basis.level_end(level)),
        [&](const tbb::blocked_range<uint32_t>& range) {
          for (uint32_t j = range.begin(); j < range.end(); ++j) {
            float* a = alpha.data() + size_t(j) * channels;
            for (const BasisValue& v : basis.coarser_basis(j)) {
              const float* coarse = alpha.data() + size_t(v.index) * channels;
              for (uint32_t c = 0; c < channels; ++c) a[c] -= v.value * coarse[c];
            }
          }
        });
  }
  return alpha;
}

}  // namespace

std::vector<float> project_samples(const BasisHierarchy& basis, std::span<const float> samples,
                                   uint32_t channels, const JobContext* job) {
  check_values(basis, samples.size(), channels, "samples");
  return coarse_to_fine(basis, samples, channels, job);
}

std::vector<float> pull_averages(const BasisHierarchy& basis, std::span<const float> samples,
                                 uint32_t channels, const JobContext* job) {
  check_values(basis, samples.size(), channels, "samples");
  std::vector<float> values(samples.begin(), samples.end());
  for (uint32_t level = basis.level_count() - 1; level-- > 0;) {
    check_cancel(job);
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(basis.level_begin(level), basis.level_end(level)),
        [&](const tbb::blocked_range<uint32_t>& range) {
          std::vector<double> sum(channels);
          for (uint32_t i = range.begin(); i < range.end(); ++i) {
            const auto children = basis.children(i);
            if (children.empty()) continue;  // nothing finer under it: keep its sample
            const BasisPoint& p = basis.point(i);
            std::fill(sum.begin(), sum.end(), 0.0);
            double weight_sum = 0.0;
            for (uint32_t child : children) {
              const BasisPoint& q = basis.point(child);
              const double w = weight(p, q.position, q.normal);
              weight_sum += w;
              const float* v = values.data() + size_t(child) * channels;
              for (uint32_t c = 0; c < channels; ++c) sum[c] += w * v[c];
            }
            float* out = values.data() + size_t(i) * channels;
            for (uint32_t c = 0; c < channels; ++c) out[c] = float(sum[c] / weight_sum);
          }
        });
  }
  return values;
}

std::vector<float> pull_push_project(const BasisHierarchy& basis, std::span<const float> samples,
                                     uint32_t channels, const JobContext* job) {
  const std::vector<float> averages = pull_averages(basis, samples, channels, job);
  return coarse_to_fine(basis, averages, channels, job);
}

bool evaluate(const BasisHierarchy& basis, std::span<const float> coefficients, uint32_t channels,
              const glm::vec3& x, const glm::vec3& n, std::span<float> out,
              std::vector<BasisValue>& scratch) {
  std::fill(out.begin(), out.begin() + channels, 0.0f);
  bool covered = false;
  for (uint32_t level = 0; level < basis.level_count(); ++level) {
    scratch.clear();
    if (!(basis.gather_basis(level, x, n, scratch) > 0.0f)) continue;
    covered = true;
    for (const BasisValue& v : scratch) {
      const float* a = coefficients.data() + size_t(v.index) * channels;
      for (uint32_t c = 0; c < channels; ++c) out[c] += v.value * a[c];
    }
  }
  return covered;
}

size_t evaluate_many(const BasisHierarchy& basis, std::span<const float> coefficients,
                     uint32_t channels, std::span<const glm::vec3> positions,
                     std::span<const glm::vec3> normals, std::span<float> out,
                     const JobContext* job) {
  check_values(basis, coefficients.size(), channels, "coefficients");
  if (normals.size() != positions.size() || out.size() != positions.size() * channels)
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless evaluate: positions, normals and out sizes disagree");
  std::atomic<size_t> uncovered{0};
  // Fixed grain: each query's result depends only on the query, so any split is
  // deterministic; 256 queries amortize the task cost and the scratch allocation.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 256),
                    [&](const tbb::blocked_range<size_t>& range) {
                      check_cancel(job);
                      std::vector<BasisValue> scratch;
                      size_t missed = 0;
                      for (size_t q = range.begin(); q < range.end(); ++q)
                        if (!evaluate(basis, coefficients, channels, positions[q], normals[q],
                                      out.subspan(q * channels, channels), scratch))
                          ++missed;
                      uncovered += missed;
                    });
  return uncovered.load();
}

FlatExpansion flatten(const BasisHierarchy& basis, std::span<const float> coefficients,
                      uint32_t channels, FlatPoints choice, uint32_t correction_passes,
                      const JobContext* job) {
  check_values(basis, coefficients.size(), channels, "coefficients");
  const uint32_t finest = basis.level_count() - 1;
  float finest_radius = 0.0f;
  for (uint32_t j = basis.level_begin(finest); j < basis.level_end(finest); ++j)
    finest_radius = std::max(finest_radius, basis.point(j).radius);

  std::vector<BasisPoint> flat_points;
  std::vector<BasisValue> scratch;
  for (uint32_t j = 0; j < basis.size(); ++j) {
    BasisPoint p = basis.point(j);
    if (choice == FlatPoints::kFinestLevel && p.level != finest) {
      scratch.clear();
      basis.gather_weights(finest, p.position, p.normal, scratch);
      if (!scratch.empty()) continue;  // the finest level covers it
    }
    if (choice == FlatPoints::kAllPointsFinestRadius) p.radius = finest_radius;
    p.level = 0;
    flat_points.push_back(p);
  }
  std::vector<glm::vec3> positions(flat_points.size()), normals(flat_points.size());
  for (size_t i = 0; i < flat_points.size(); ++i) {
    positions[i] = flat_points[i].position;
    normals[i] = flat_points[i].normal;
  }
  const size_t values = flat_points.size() * channels;
  // One level: the constructor's stable sort keeps the order, so flat point i is flat_points[i].
  FlatExpansion flat{BasisHierarchy(std::move(flat_points)), std::vector<float>(values), channels};
  std::vector<float> target(values), residual(values);
  evaluate_many(basis, coefficients, channels, positions, normals, target, job);
  flat.coefficients = target;
  for (uint32_t pass = 0; pass < correction_passes; ++pass) {
    evaluate_many(flat.basis, flat.coefficients, channels, positions, normals, residual, job);
    for (size_t i = 0; i < values; ++i) flat.coefficients[i] += target[i] - residual[i];
  }
  return flat;
}

}  // namespace bakegi::meshless
