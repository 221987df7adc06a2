// Whether two surface points see each other along the surface: the segment between them,
// both ends lifted off their surfaces along their normals by
//
//   lift = base_lift + per_distance · |a − b|,
//
// crosses no geometry. The distance-proportional part keeps the segment outside gently
// curved (tessellated) surfaces between the two points; any occluder taller than the lift
// standing between them still blocks. Used where values stored at surface samples are
// interpolated at bake points (the antiradiance splat, the meshless evaluation), so that a
// point does not take light from samples behind a wall or under a box.
#pragma once

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"

namespace bakegi {

inline bool lifted_points_see_each_other(const RayTracer& tracer, const glm::vec3& a,
                                         const glm::vec3& a_normal, const glm::vec3& b,
                                         const glm::vec3& b_normal, float base_lift,
                                         float per_distance) {
  const float distance = glm::length(a - b);
  if (!(distance > 0.0f)) return true;
  const float lift = base_lift + per_distance * distance;
  const glm::vec3 from = a + lift * a_normal;
  const glm::vec3 to = b + lift * b_normal;
  Ray ray;
  ray.origin = from;
  ray.direction = to - from;  // t in (0, 1) spans the segment
  ray.tnear = 0.0f;
  ray.tfar = 1.0f;
  return !tracer.occluded(ray);
}

}  // namespace bakegi
