#include "solvers/meshless/visible_basis.h"

#include <algorithm>
#include <atomic>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/lifted_visibility.h"
#include "scene/ray_tracer.h"
#include "solvers/meshless/visible_evaluation.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::meshless {

bool sees_basis_point(const RayTracer& tracer, const glm::vec3& x, const glm::vec3& n,
                      const BasisPoint& p) {
  return lifted_points_see_each_other(tracer, x, n, p.position, p.normal, kLiftOfRadius * p.radius,
                                      kLiftPerDistance);
}

float gather_visible_basis(const BasisHierarchy& basis, const RayTracer* tracer, uint32_t level,
                           const glm::vec3& x, const glm::vec3& n, std::vector<BasisValue>& out,
                           std::vector<BasisValue>& candidates, uint64_t& rays) {
  candidates.clear();
  basis.gather_weights(level, x, n, candidates);
  double sum = 0.0;
  const size_t begin = out.size();
  for (const BasisValue& c : candidates) {
    if (!(c.value > 0.0f)) continue;
    if (tracer != nullptr) {
      ++rays;
      if (!sees_basis_point(*tracer, x, n, basis.point(c.index))) continue;
    }
    sum += c.value;
    out.push_back(c);
  }
  if (!(sum > 0.0)) {
    out.resize(begin);
    return 0.0f;
  }
  for (size_t k = begin; k < out.size(); ++k) out[k].value = float(double(out[k].value) / sum);
  return float(sum);
}

VisibleRelations visible_relations(const BasisHierarchy& basis, const RayTracer* tracer,
                                   const JobContext* job) {
  const size_t n = basis.size();
  constexpr size_t kBlock = 128;
  const size_t blocks = (n + kBlock - 1) / kBlock;
  // Each block's rows, joined in block order: the result does not depend on the thread count.
  std::vector<std::vector<BasisValue>> block_pull(blocks), block_coarser(blocks);
  std::vector<uint64_t> pull_sizes(n, 0), coarser_sizes(n, 0);
  std::atomic<uint64_t> rays{0}, blocked{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, blocks, 1), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<BasisValue> candidates;
        for (size_t block = range.begin(); block < range.end(); ++block) {
          if (job != nullptr && job->is_cancelled()) return;
          uint64_t local_rays = 0, local_blocked = 0;
          std::vector<BasisValue>& pull = block_pull[block];
          std::vector<BasisValue>& coarser = block_coarser[block];
          const size_t end = std::min(n, (block + 1) * kBlock);
          for (size_t index = block * kBlock; index < end; ++index) {
            const uint32_t i = uint32_t(index);
            const BasisPoint& p = basis.point(i);
            // Pull: children of i that see p_i, weighted by i's own kernel.
            const size_t pull_begin = pull.size();
            double weight_sum = 0.0;
            for (uint32_t child : basis.children(i)) {
              const BasisPoint& q = basis.point(child);
              const float w = weight(p, q.position, q.normal);
              if (!(w > 0.0f)) continue;
              if (tracer != nullptr) {
                ++local_rays;
                if (!sees_basis_point(*tracer, q.position, q.normal, p)) {
                  ++local_blocked;
                  continue;
                }
              }
              weight_sum += w;
              pull.push_back({child, w});
            }
            for (size_t k = pull_begin; k < pull.size(); ++k)
              pull[k].value = float(double(pull[k].value) / weight_sum);
            pull_sizes[i] = pull.size() - pull_begin;
            // Coarser: per coarser level, the functions p_j sees, renormalized.
            const size_t coarser_begin = coarser.size();
            for (uint32_t level = 0; level < p.level; ++level) {
              const size_t before = coarser.size();
              gather_visible_basis(basis, tracer, level, p.position, p.normal, coarser, candidates,
                                   local_rays);
              if (tracer != nullptr) {
                candidates.erase(
                    std::remove_if(candidates.begin(), candidates.end(),
                                   [](const BasisValue& c) { return !(c.value > 0.0f); }),
                    candidates.end());
                local_blocked += candidates.size() - (coarser.size() - before);
              }
            }
            coarser_sizes[i] = coarser.size() - coarser_begin;
          }
          rays += local_rays;
          blocked += local_blocked;
        }
      });
  if (job != nullptr) job->throw_if_cancelled();
  VisibleRelations relations;
  relations.pull_offsets.assign(n + 1, 0);
  relations.coarser_offsets.assign(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    relations.pull_offsets[i + 1] = relations.pull_offsets[i] + pull_sizes[i];
    relations.coarser_offsets[i + 1] = relations.coarser_offsets[i] + coarser_sizes[i];
  }
  relations.pull.reserve(relations.pull_offsets.back());
  relations.coarser.reserve(relations.coarser_offsets.back());
  for (size_t b = 0; b < blocks; ++b) {
    relations.pull.insert(relations.pull.end(), block_pull[b].begin(), block_pull[b].end());
    relations.coarser.insert(relations.coarser.end(), block_coarser[b].begin(),
                             block_coarser[b].end());
  }
  relations.rays = rays.load();
  relations.blocked = blocked.load();
  return relations;
}

std::vector<float> visible_pull_push_project(const BasisHierarchy& basis,
                                             const VisibleRelations& relations,
                                             std::span<const float> samples, uint32_t channels,
                                             const JobContext* job) {
  if (channels == 0 || samples.size() != basis.size() * channels ||
      relations.pull_offsets.size() != basis.size() + 1) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless visible projection: samples hold " + std::to_string(samples.size()) +
                    " floats, expected points x channels, with relations of the same basis");
  }
  std::vector<float> values(samples.begin(), samples.end());
  // Pull, fine to coarse: each level reads only the next finer one.
  for (uint32_t level = basis.level_count() - 1; level-- > 0;) {
    if (job != nullptr) job->throw_if_cancelled();
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(basis.level_begin(level), basis.level_end(level)),
        [&](const tbb::blocked_range<uint32_t>& range) {
          std::vector<double> sum(channels);
          for (uint32_t i = range.begin(); i < range.end(); ++i) {
            const auto pull = relations.pull_of(i);
            if (pull.empty()) continue;  // no visible child: keep its own sample
            std::fill(sum.begin(), sum.end(), 0.0);
            for (const BasisValue& c : pull) {
              const float* v = values.data() + size_t(c.index) * channels;
              for (uint32_t k = 0; k < channels; ++k) sum[k] += double(c.value) * v[k];
            }
            float* out = values.data() + size_t(i) * channels;
            for (uint32_t k = 0; k < channels; ++k) out[k] = float(sum[k]);
          }
        });
  }
  // Push (Eq. 7), coarse to fine: a level reads only coarser ones.
  for (uint32_t level = 1; level < basis.level_count(); ++level) {
    if (job != nullptr) job->throw_if_cancelled();
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(basis.level_begin(level), basis.level_end(level)),
        [&](const tbb::blocked_range<uint32_t>& range) {
          for (uint32_t j = range.begin(); j < range.end(); ++j) {
            float* a = values.data() + size_t(j) * channels;
            for (const BasisValue& v : relations.coarser_of(j)) {
              const float* coarse = values.data() + size_t(v.index) * channels;
              for (uint32_t c = 0; c < channels; ++c) a[c] -= v.value * coarse[c];
            }
          }
        });
  }
  return values;
}

}  // namespace bakegi::meshless
