// The optional visibility approximation for the indirect bounce (issue 17, item 7): the
// paper's VPL light has none, so light leaks through walls and under tables (its §5). Here
// VPLs are grouped into spatial clusters (contiguous runs along a Morton curve) and a
// receiver traces one shadow ray per cluster, to the cluster's VPL nearest its flux-weighted
// centre; a blocked ray removes the whole cluster's light. Cost: clusters rays per receiver
// (per subsplat in the preview, per point subsplat in the bake).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/splatting/virtual_point_lights.h"

namespace bakegi {

class RayTracer;

struct VplClusters {
  std::vector<size_t> begin;      // cluster c holds VPLs [begin[c], begin[c + 1])
  std::vector<glm::vec3> anchor;  // where its shadow rays end
  size_t count() const { return anchor.size(); }
};

// Reorders `vpls` along a Morton curve and cuts them into `count` clusters of about equal
// size (fewer when there are fewer VPLs).
VplClusters cluster_vpls(VirtualPointLights& vpls, uint32_t count);

// The light of the VPLs [begin, end) at the receiver, as the caller computes it.
using VplRangeLight = std::function<glm::vec3(size_t begin, size_t end)>;

// Light at a receiver with one shadow ray per cluster: each unblocked cluster adds
// range_light over its VPLs; `epsilon` offsets the ray's start off the receiver. Counts the
// shadow rays into `rays`.
glm::vec3 visible_vpl_light(const VplClusters& clusters, const RayTracer& tracer, float epsilon,
                            const glm::vec3& position, const glm::vec3& geometric_normal,
                            const VplRangeLight& range_light, uint64_t& rays);

}  // namespace bakegi
