#include "bake/point_sharing.h"

#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/mutual_visibility.h"
#include "scene/ray_tracer.h"
#include "util/error.h"

namespace bakegi {

namespace {

// Whether points a and b see the same light: normals alike and nothing between them.
bool can_share(const BakePoints& points, uint32_t a, uint32_t b, const RayTracer& tracer,
               float ray_epsilon) {
  const glm::vec3& na = points.normals[a];
  const glm::vec3& nb = points.normals[b];
  if (!(glm::dot(na, nb) >= kSharedNormalCosine)) return false;
  return points_see_each_other(tracer, points.positions[a], na, points.positions[b], nb,
                               ray_epsilon);
}

// Groups whose candidate was blocked keep trying the points of their group evaluated so far;
// this many at most (a vertex with more separate lights than this is not worth the rays).
constexpr size_t kMaxTriesPerGroup = 8;

}  // namespace

SharedPoints share_points(const BakePoints& points, const RayTracer& tracer, float ray_epsilon) {
  SharedPoints shared;
  const std::vector<uint32_t>& candidates = points.share_candidates;
  const size_t count = points.size();
  if (candidates.size() != count) return shared;
  bool any = false;
  for (size_t i = 0; i < count && !any; ++i) any = candidates[i] != i;
  if (!any) return shared;

  // First try every point against its candidate, in parallel (one ray each).
  std::vector<uint8_t> shares_candidate(count, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t i = block.begin(); i != block.end(); ++i) {
                        const uint32_t c = candidates[i];
                        if (c != i && can_share(points, c, uint32_t(i), tracer, ray_epsilon)) {
                          shares_candidate[i] = 1;
                        }
                      }
                    });

  // Then number the distinct points in order; a blocked point tries the other points of its
  // group evaluated so far (the other side of a wall has its own).
  shared.distinct_index.assign(count, 0);
  std::vector<std::vector<uint32_t>> others;  // per group with blocked points: its evaluated
  std::vector<int32_t> others_of(count, -1);  // points besides the first; by first point
  auto add_distinct = [&](uint32_t i) {
    shared.distinct_index[i] = uint32_t(shared.distinct.positions.size());
    shared.distinct.positions.push_back(points.positions[i]);
    shared.distinct.normals.push_back(points.normals[i]);
    shared.distinct.object_ids.push_back(points.object_ids[i]);
  };
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t c = candidates[i];
    if (c == i) {
      add_distinct(i);
    } else if (shares_candidate[i]) {
      shared.distinct_index[i] = shared.distinct_index[c];
    } else {
      if (others_of[c] < 0) {
        others_of[c] = int32_t(others.size());
        others.emplace_back();
      }
      std::vector<uint32_t>& tried = others[size_t(others_of[c])];
      bool found = false;
      for (uint32_t j : tried) {
        if (can_share(points, j, i, tracer, ray_epsilon)) {
          shared.distinct_index[i] = shared.distinct_index[j];
          found = true;
          break;
        }
      }
      if (!found) {
        add_distinct(i);
        if (tried.size() < kMaxTriesPerGroup) tried.push_back(i);
      }
    }
  }
  if (shared.distinct.size() == count) return {};
  return shared;
}

void spread_shared_values(const SharedPoints& shared, const std::vector<glm::vec3>& distinct,
                          std::vector<glm::vec3>& out) {
  if (distinct.size() != shared.distinct.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "shared point values do not match the distinct points");
  }
  out.resize(shared.distinct_index.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = distinct[shared.distinct_index[i]];
}

}  // namespace bakegi
