// Whether two surface points see each other: one ray between them, each lifted off its
// surface along its normal, so that neither surface blocks it.
#pragma once

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"

namespace bakegi {

inline bool points_see_each_other(const RayTracer& tracer, const glm::vec3& a,
                                  const glm::vec3& normal_a, const glm::vec3& b,
                                  const glm::vec3& normal_b, float ray_epsilon) {
  const glm::vec3 from = a + normal_a * ray_epsilon;
  const glm::vec3 to = b + normal_b * ray_epsilon;
  const glm::vec3 span = to - from;
  const float length = glm::length(span);
  if (!(length > 0.0f)) return true;
  return !tracer.occluded(Ray{from, span / length, 0.0f, length});
}

}  // namespace bakegi
