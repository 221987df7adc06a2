// Where a bake checks itself: probe points at which the path tracer's estimate is compared
// with what the bake delivers there (bake/error_estimate.h).
//
// A probe's baked value is a weighted sum of up to four bake points' results: 1 x the bake
// point itself for probes placed at bake points (the solver's own error), or the barycentric
// weights of a face's corners for probes placed inside faces ("display probes": what a viewer
// shows between the vertices of a color attribute, interpolation included).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "scene/bake_points.h"

namespace bakegi {

struct ErrorProbes {
  BakePoints points;  // position, shading normal and object id of every probe
  std::vector<std::array<uint32_t, 4>> stencil_points;  // bake point indices
  std::vector<std::array<float, 4>> stencil_weights;    // >= 0; unused entries weigh 0
  // Per probe: 1 / (n q) for a probe drawn with probability q among n points, so that
  // weighted means over the probes estimate means over the points (1 when drawn uniformly).
  std::vector<float> sampling_weights;

  size_t size() const { return points.size(); }
  void add(const glm::vec3& position, const glm::vec3& normal, uint32_t object_id,
           const std::array<uint32_t, 4>& indices, const std::array<float, 4>& weights,
           float sampling_weight = 1.0f);
  float sampling_weight(size_t i) const {
    return i < sampling_weights.size() ? sampling_weights[i] : 1.0f;
  }
  // The value the bake delivers at probe `i`.
  glm::vec3 baked_value(size_t i, const std::vector<glm::vec3>& baked) const;
};

// `count` distinct bake points drawn uniformly (all of them when there are fewer), each a
// probe of weight 1 on itself. Deterministic for a seed.
ErrorProbes probes_at_bake_points(const BakePoints& points, size_t count, uint64_t seed);

// `count` probes at bake points drawn with replacement, half uniformly and half in
// proportion to the bake's luminance there (`baked`, one value per point), each weighted by
// 1 / (n q) (sampling_weights). Why: a bake's error is mostly where its light is, and where
// a few bright points carry it (the corners of a maze's sunlit cell: 5 of 2,000 points, 70%
// of the squared error) 256 uniform probes seldom meet them, so the estimate came out 0.64x
// the true error; the uniform half keeps dark points (where a method may miss light
// altogether) drawn at least half as often as before. All points, uniformly, when there
// are at most `count`; uniform when the bake is black. Deterministic for a seed.
ErrorProbes probes_weighted_by_light(const BakePoints& points, const std::vector<glm::vec3>& baked,
                                     size_t count, uint64_t seed);

// Checks probes given from outside (the C API): finite positions in range, non-zero normals
// (normalized here), indices below `bake_point_count`, finite non-negative weights with a
// positive sum. Throws Error(INVALID_ARGUMENT) naming the probe.
void check_error_probes(ErrorProbes& probes, size_t bake_point_count);

}  // namespace bakegi
