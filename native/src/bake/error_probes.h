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

#include "bake_points/bake_points.h"

namespace bakegi {

struct ErrorProbes {
  BakePoints points;  // position, shading normal and object id of every probe
  std::vector<std::array<uint32_t, 4>> stencil_points;  // bake point indices
  std::vector<std::array<float, 4>> stencil_weights;    // >= 0; unused entries weigh 0

  size_t size() const { return points.size(); }
  void add(const glm::vec3& position, const glm::vec3& normal, uint32_t object_id,
           const std::array<uint32_t, 4>& indices, const std::array<float, 4>& weights);
  // The value the bake delivers at probe `i`.
  glm::vec3 baked_value(size_t i, const std::vector<glm::vec3>& baked) const;
};

// `count` distinct bake points drawn uniformly (all of them when there are fewer), each a
// probe of weight 1 on itself. Deterministic for a seed.
ErrorProbes probes_at_bake_points(const BakePoints& points, size_t count, uint64_t seed);

// Checks probes given from outside (the C API): finite positions in range, non-zero normals
// (normalized here), indices below `bake_point_count`, finite non-negative weights with a
// positive sum. Throws Error(INVALID_ARGUMENT) naming the probe.
void check_error_probes(ErrorProbes& probes, size_t bake_point_count);

}  // namespace bakegi
