#include "solvers/meshless/visible_evaluation.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/lifted_visibility.h"
#include "scene/ray_tracer.h"
#include "solvers/meshless/level_completion.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::meshless {

namespace {

bool sees(const RayTracer& tracer, const glm::vec3& x, const glm::vec3& n, const BasisPoint& p) {
  return lifted_points_see_each_other(tracer, x, n, p.position, p.normal, kLiftOfRadius * p.radius,
                                      kLiftPerDistance);
}

// The fraction of the cosine-weighted hemisphere at x whose rays travel farther than
// `distance` (or escape): about 0 in a gap narrower than that, about 1 on an open surface.
// kOpennessRays jittered strata, the same for a point every time (seeded by its index).
float openness(const RayTracer& tracer, const glm::vec3& x, const glm::vec3& n, float distance,
               uint64_t point, uint64_t& rays) {
  constexpr uint32_t kSide = 4;
  const Frame frame(n);
  const glm::vec3 origin = x + n * (1e-4f * distance);
  RandomStream rng = sample_stream(0x6f70656eull, point, 0);
  uint32_t open = 0;
  for (uint32_t k = 0; k < kSide * kSide; ++k) {
    const float u1 = (float(k % kSide) + rng.next_float()) / float(kSide);
    const float u2 = (float(k / kSide) + rng.next_float()) / float(kSide);
    const glm::vec3 direction = frame.to_world(sample_cosine_hemisphere(u1, u2));
    open += tracer.occluded(Ray{origin, direction, 0.0f, distance}) ? 0 : 1;
  }
  rays += kSide * kSide;
  return float(open) / float(kSide * kSide);
}

}  // namespace

void EvaluationWeights::apply(std::span<const float> coefficients, uint32_t channels,
                              std::span<float> out) const {
  const size_t points = point_count();
  if (out.size() != points * channels) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless evaluation weights: output size");
  }
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, points, 256), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<double> sum(channels);
        for (size_t q = range.begin(); q < range.end(); ++q) {
          std::fill(sum.begin(), sum.end(), 0.0);
          for (uint64_t e = offsets[q]; e < offsets[q + 1]; ++e) {
            const float* a = coefficients.data() + size_t(entries[e].index) * channels;
            for (uint32_t c = 0; c < channels; ++c) {
              sum[c] += double(entries[e].value) * a[c];
            }
          }
          for (uint32_t c = 0; c < channels; ++c) out[q * channels + c] = float(sum[c]);
        }
      });
}

VisibleEvaluationStats visible_weights(const BasisHierarchy& basis, const RayTracer* tracer,
                                       std::span<const glm::vec3> positions,
                                       std::span<const glm::vec3> normals,
                                       EvaluationWeights& weights, JobContext* job,
                                       const VisibleRelations* completion) {
  if (normals.size() != positions.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless visible evaluation: positions and normals sizes disagree");
  }
  constexpr size_t kBlock = 64;
  const size_t blocks = (positions.size() + kBlock - 1) / kBlock;
  // Each block's rows, joined in block order afterwards: the result does not depend on the
  // thread count.
  std::vector<std::vector<BasisValue>> block_entries(blocks);
  std::vector<uint64_t> row_sizes(positions.size(), 0);
  std::atomic<uint64_t> rays{0}, blocked{0}, skipped{0}, blind{0}, uncovered{0}, completed{0};
  std::atomic<size_t> done{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, blocks, 1), [&](const tbb::blocked_range<size_t>& block_range) {
        for (size_t block = block_range.begin(); block < block_range.end(); ++block) {
          if (job != nullptr && job->is_cancelled()) return;
          std::vector<BasisValue>& rows = block_entries[block];
          std::vector<BasisValue> candidates, seen_row, all_row;
          std::vector<char> visible;
          uint64_t local_rays = 0, local_blocked = 0, local_skipped = 0, local_blind = 0,
                   local_uncovered = 0, local_completed = 0;
          const size_t end = std::min(positions.size(), (block + 1) * kBlock);
          for (size_t q = block * kBlock; q < end; ++q) {
            const glm::vec3& x = positions[q];
            const glm::vec3& n = normals[q];
            seen_row.clear();
            all_row.clear();
            bool covered = false, sees_any = false;
            float smallest_radius = std::numeric_limits<float>::max();
            uint64_t blind_levels = 0;
            for (uint32_t level = 0; level < basis.level_count(); ++level) {
              candidates.clear();
              basis.gather_weights(level, x, n, candidates);
              double all_weight = 0.0, visible_weight = 0.0;
              visible.assign(candidates.size(), 0);
              for (size_t k = 0; k < candidates.size(); ++k) {
                const BasisValue& c = candidates[k];
                if (!(c.value > 0.0f)) continue;
                all_weight += c.value;
                smallest_radius = std::min(smallest_radius, basis.point(c.index).radius);
                if (tracer == nullptr) {
                  visible[k] = 1;
                  visible_weight += c.value;
                  continue;
                }
                ++local_rays;
                if (sees(*tracer, x, n, basis.point(c.index))) {
                  visible[k] = 1;
                  visible_weight += c.value;
                } else {
                  ++local_blocked;
                }
              }
              if (!(all_weight > 0.0)) continue;
              covered = true;
              if (visible_weight > 0.0) {
                sees_any = true;
              } else {
                ++blind_levels;
              }
              for (size_t k = 0; k < candidates.size(); ++k) {
                const BasisValue& c = candidates[k];
                if (!(c.value > 0.0f)) continue;
                all_row.push_back({c.index, float(double(c.value) / all_weight)});
                if (visible[k])
                  seen_row.push_back({c.index, float(double(c.value) / visible_weight)});
              }
            }
            if (!covered) ++local_uncovered;
            // A level none of whose functions the point sees adds nothing of its own (its light
            // does not reach the point); below a level it sees, the completion gives it what
            // that level's coefficients were made the differences from (level_completion.h).
            // A point that sees no function of any level gets the unblocked value scaled by
            // how open its surroundings are (see the header).
            if (sees_any) {
              local_skipped += blind_levels;
              if (completion != nullptr) {
                local_completed += complete_missing_levels(basis, *completion, seen_row);
              }
            } else if (covered) {
              ++local_blind;
              const float open =
                  tracer == nullptr
                      ? 1.0f
                      : openness(*tracer, x, n, smallest_radius, uint64_t(q), local_rays);
              seen_row.clear();
              if (open > 0.0f) {
                for (const BasisValue& b : all_row) seen_row.push_back({b.index, b.value * open});
              }
            }
            rows.insert(rows.end(), seen_row.begin(), seen_row.end());
            row_sizes[q] = seen_row.size();
          }
          rays += local_rays;
          blocked += local_blocked;
          skipped += local_skipped;
          blind += local_blind;
          uncovered += local_uncovered;
          completed += local_completed;
          const size_t finished = done.fetch_add(end - block * kBlock) + (end - block * kBlock);
          if (job != nullptr) job->set_stage_progress(double(finished) / double(positions.size()));
        }
      });
  if (job != nullptr) job->throw_if_cancelled();
  weights.offsets.assign(positions.size() + 1, 0);
  for (size_t q = 0; q < positions.size(); ++q) {
    weights.offsets[q + 1] = weights.offsets[q] + row_sizes[q];
  }
  weights.entries.clear();
  weights.entries.reserve(weights.offsets.back());
  for (const auto& rows : block_entries) {
    weights.entries.insert(weights.entries.end(), rows.begin(), rows.end());
  }
  VisibleEvaluationStats stats;
  stats.rays = rays.load();
  stats.blocked = blocked.load();
  stats.levels_skipped = skipped.load();
  stats.points_blind = blind.load();
  stats.uncovered = size_t(uncovered.load());
  stats.levels_completed = completed.load();
  return stats;
}

VisibleEvaluationStats evaluate_visible_many(const BasisHierarchy& basis,
                                             std::span<const float> coefficients, uint32_t channels,
                                             const RayTracer& tracer,
                                             std::span<const glm::vec3> positions,
                                             std::span<const glm::vec3> normals,
                                             std::span<float> out, JobContext* job) {
  if (channels == 0 || coefficients.size() != basis.size() * channels) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless visible evaluation: coefficients hold " +
                                                   std::to_string(coefficients.size()) +
                                                   " floats, expected points x channels");
  }
  if (normals.size() != positions.size() || out.size() != positions.size() * channels) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless visible evaluation: positions, normals and out sizes disagree");
  }
  EvaluationWeights weights;
  const VisibleEvaluationStats stats =
      visible_weights(basis, &tracer, positions, normals, weights, job);
  weights.apply(coefficients, channels, out);
  return stats;
}

}  // namespace bakegi::meshless
