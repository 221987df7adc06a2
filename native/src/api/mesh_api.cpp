// bakegi_mesh_*: mesh helpers behind the C API (levels of detail: mesh/mesh_simplify.h).
#include <algorithm>

#include "api/api_guard.h"
#include "mesh/mesh_simplify.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

extern "C" {

bakegi_status bakegi_mesh_simplify(const float* positions, uint64_t vertex_count,
                                   const uint32_t* indices, uint64_t index_count,
                                   float target_ratio, float max_error, uint32_t* out_indices,
                                   uint64_t* out_index_count, float* out_error) {
  return guarded(__func__, [&] {
    require(out_index_count, "out_index_count");
    if (vertex_count > (uint64_t(1) << 32) || index_count > (uint64_t(1) << 34)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "the mesh is too large to simplify");
    }
    if (vertex_count > 0) require(positions, "positions");
    if (index_count > 0) {
      require(indices, "indices");
      require(out_indices, "out_indices");
    }
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
    const bakegi::SimplifiedTriangles simplified = bakegi::simplify_triangles(
        {reinterpret_cast<const glm::vec3*>(positions), size_t(vertex_count)},
        {indices, size_t(index_count)}, target_ratio, max_error);
    std::copy(simplified.indices.begin(), simplified.indices.end(), out_indices);
    *out_index_count = simplified.indices.size();
    if (out_error) *out_error = simplified.relative_error;
  });
}

}  // extern "C"
