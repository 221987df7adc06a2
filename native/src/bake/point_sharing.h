// Bake points that share one value. The exporter names, per point, an earlier point at the
// same place with the same normal (BakePoints::share_candidates: the corners of one vertex);
// the light there is the same unless another surface meets the mesh at that place (a wall
// standing on the vertex puts the corners on its two sides in two different lights). So a
// point shares its candidate's value only when the normals agree and a ray between the two
// points, each lifted off its surface by the ray epsilon, is unblocked; a point blocked from
// its candidate tries the group's other evaluated points, and else is evaluated itself.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/bake_points.h"

namespace bakegi {

class RayTracer;

struct SharedPoints {
  BakePoints distinct;                  // the points to evaluate
  std::vector<uint32_t> distinct_index;  // per bake point, its value's index in `distinct`
};

// Normals closer than this (cosine of 2.6 degrees) count as the same: the exporter rounds
// them at 0.06 degrees, so a group's normals differ by rounding only.
inline constexpr float kSharedNormalCosine = 0.999f;

// Empty distinct_index when no point shares (evaluate `points` themselves).
SharedPoints share_points(const BakePoints& points, const RayTracer& tracer, float ray_epsilon);

// Spreads the values of the distinct points to every bake point.
void spread_shared_values(const SharedPoints& shared, const std::vector<glm::vec3>& distinct,
                          std::vector<glm::vec3>& out);

}  // namespace bakegi
