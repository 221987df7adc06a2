#include "solvers/meshless/visible_evaluation.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/ray_tracer.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::meshless {

namespace {

bool sees(const RayTracer& tracer, const glm::vec3& x, const glm::vec3& n, const BasisPoint& p) {
  const float distance = glm::length(x - p.position);
  if (!(distance > 0.0f)) return true;
  const float lift = kLiftOfRadius * p.radius + kLiftPerDistance * distance;
  const glm::vec3 from = x + lift * n;
  const glm::vec3 to = p.position + lift * p.normal;
  Ray ray;
  ray.origin = from;
  ray.direction = to - from;  // t in (0, 1) spans the segment
  ray.tnear = 0.0f;
  ray.tfar = 1.0f;
  return !tracer.occluded(ray);
}

}  // namespace

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
  std::atomic<uint64_t> rays{0}, blocked{0}, skipped{0}, unblocked{0}, uncovered{0};
  std::atomic<size_t> done{0};
  // Fixed grain; each query's result depends only on the query (deterministic).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 64),
                    [&](const tbb::blocked_range<size_t>& range) {
                      if (job != nullptr && job->is_cancelled()) return;
                      std::vector<BasisValue> candidates;
                      std::vector<char> visible;
                      std::vector<double> seen(channels), all(channels);
                      uint64_t local_rays = 0, local_blocked = 0, local_skipped = 0,
                               local_unblocked = 0, local_uncovered = 0;
                      for (size_t q = range.begin(); q < range.end(); ++q) {
                        const glm::vec3& x = positions[q];
                        const glm::vec3& n = normals[q];
                        std::fill(seen.begin(), seen.end(), 0.0);
                        std::fill(all.begin(), all.end(), 0.0);
                        bool covered = false, sees_any = false;
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
                            ++local_rays;
                            if (sees(tracer, x, n, basis.point(c.index))) {
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
                            const float* a = coefficients.data() + size_t(c.index) * channels;
                            const double b_all = double(c.value) / all_weight;
                            const double b_seen =
                                visible[k] ? double(c.value) / visible_weight : 0.0;
                            for (uint32_t ch = 0; ch < channels; ++ch) {
                              all[ch] += b_all * a[ch];
                              seen[ch] += b_seen * a[ch];
                            }
                          }
                        }
                        if (!covered) ++local_uncovered;
                        // A level none of whose functions the point sees adds nothing (its light
                        // does not reach the point); a point that sees no function of any level
                        // gets the unblocked value (no better information).
                        const std::vector<double>& value = sees_any ? seen : all;
                        if (sees_any) {
                          local_skipped += blind_levels;
                        } else if (covered) {
                          ++local_unblocked;
                        }
                        float* result = out.data() + q * channels;
                        for (uint32_t ch = 0; ch < channels; ++ch) result[ch] = float(value[ch]);
                      }
                      rays += local_rays;
                      blocked += local_blocked;
                      skipped += local_skipped;
                      unblocked += local_unblocked;
                      uncovered += local_uncovered;
                      const size_t finished = done.fetch_add(range.size()) + range.size();
                      if (job != nullptr)
                        job->set_stage_progress(double(finished) / double(positions.size()));
                    });
  if (job != nullptr) job->throw_if_cancelled();
  VisibleEvaluationStats stats;
  stats.rays = rays.load();
  stats.blocked = blocked.load();
  stats.levels_skipped = skipped.load();
  stats.points_unblocked = unblocked.load();
  stats.uncovered = size_t(uncovered.load());
  return stats;
}

}  // namespace bakegi::meshless
