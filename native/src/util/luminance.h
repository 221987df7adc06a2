// Luminance Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709): the quantity of every error
// metric, estimate and energy check in the project, in double precision.
#pragma once

#include <glm/glm.hpp>

namespace bakegi {

inline double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
inline double luminance(const glm::vec3& c) { return luminance(glm::dvec3(c)); }

}  // namespace bakegi
