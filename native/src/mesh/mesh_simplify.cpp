#include "mesh/mesh_simplify.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <meshoptimizer.h>

#include "util/error.h"

namespace bakegi {

SimplifiedTriangles simplify_triangles(std::span<const glm::vec3> positions,
                                       std::span<const uint32_t> indices, double target_ratio,
                                       float max_relative_error) {
  if (indices.size() % 3 != 0) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "the index count is not a multiple of 3");
  }
  if (!(target_ratio > 0.0 && target_ratio <= 1.0)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "target ratio must lie in (0, 1]");
  }
  if (!(max_relative_error >= 0.0f && std::isfinite(max_relative_error))) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "max error must be finite and not negative");
  }
  for (const uint32_t index : indices) {
    if (index >= positions.size()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "index " + std::to_string(index) + " is past the " +
                      std::to_string(positions.size()) + " vertices");
    }
  }
  for (const glm::vec3& p : positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "a vertex position is not finite");
    }
  }
  SimplifiedTriangles result;
  if (indices.empty()) return result;
  const size_t triangles = indices.size() / 3;
  const size_t target_triangles =
      std::max<size_t>(1, size_t(std::llround(double(triangles) * target_ratio)));
  result.indices.resize(indices.size());  // the simplifier's worst case: nothing collapses
  const float* xyz = &positions[0].x;
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
#if MESHOPTIMIZER_VERSION >= 180
  const size_t count = meshopt_simplify(result.indices.data(), indices.data(), indices.size(), xyz,
                                        positions.size(), sizeof(glm::vec3), target_triangles * 3,
                                        max_relative_error, 0, &result.relative_error);
#elif MESHOPTIMIZER_VERSION >= 160
  const size_t count = meshopt_simplify(result.indices.data(), indices.data(), indices.size(), xyz,
                                        positions.size(), sizeof(glm::vec3), target_triangles * 3,
                                        max_relative_error, &result.relative_error);
#else  // Debian 11's 0.15 (the portable build) does not report its error
  const size_t count =
      meshopt_simplify(result.indices.data(), indices.data(), indices.size(), xyz, positions.size(),
                       sizeof(glm::vec3), target_triangles * 3, max_relative_error);
  result.relative_error = std::nanf("");
#endif
  result.indices.resize(count);
  return result;
}

}  // namespace bakegi
