#include "grid/grid_layout.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "util/error.h"

namespace bakegi {

namespace {

constexpr uint32_t kDefaultCellsOnLongestAxis = 32;

void check_bounds(const glm::vec3& lo, const glm::vec3& hi) {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a])) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid bounds must be finite");
    }
    if (hi[a] < lo[a]) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "grid bounds are inverted: the maximum is below the minimum on axis " +
                      std::to_string(a));
    }
  }
}

uint64_t product(const std::array<uint32_t, 3>& r) {
  return uint64_t(r[0]) * r[1] * r[2];
}

}  // namespace

GridLayout make_grid_layout(const glm::vec3& bounds_min, const glm::vec3& bounds_max,
                            const std::array<uint32_t, 3>& resolution) {
  check_bounds(bounds_min, bounds_max);
  for (uint32_t r : resolution) {
    if (r < kMinGridResolution || r > kMaxGridResolution) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid resolution " + std::to_string(r) +
                                                     " per axis is outside [" +
                                                     std::to_string(kMinGridResolution) + ", " +
                                                     std::to_string(kMaxGridResolution) + "]");
    }
  }
  GridLayout layout;
  layout.bounds_min = bounds_min;
  layout.bounds_max = bounds_max;
  layout.resolution = resolution;
  // A flat axis gets the width of one of the other axes' cells, centred on the plane.
  float widest_cell = 0.0f;
  for (int a = 0; a < 3; ++a) {
    widest_cell = std::max(widest_cell, (bounds_max[a] - bounds_min[a]) / float(resolution[a]));
  }
  if (!(widest_cell > 0.0f)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid bounds are a single point");
  }
  for (int a = 0; a < 3; ++a) {
    const float cell = (bounds_max[a] - bounds_min[a]) / float(resolution[a]);
    if (cell < 1e-6f * widest_cell) {
      const float centre = 0.5f * (bounds_min[a] + bounds_max[a]);
      const float half = 0.5f * widest_cell * float(resolution[a]);
      layout.bounds_min[a] = centre - half;
      layout.bounds_max[a] = centre + half;
    }
  }
  return layout;
}

GridLayout choose_grid_layout(const glm::vec3& bounds_min, const glm::vec3& bounds_max,
                              float cell_size, uint64_t max_vertices) {
  check_bounds(bounds_min, bounds_max);
  if (!std::isfinite(cell_size) || cell_size < 0.0f) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid cell size must be finite and >= 0");
  }
  if (max_vertices < 8) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "a grid needs at least 8 vertices (2 per axis)");
  }
  const glm::vec3 extent = bounds_max - bounds_min;
  const float longest = std::max({extent.x, extent.y, extent.z});
  if (!(longest > 0.0f))
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid bounds are a single point");
  float cell = cell_size > 0.0f ? cell_size : longest / float(kDefaultCellsOnLongestAxis);
  std::array<uint32_t, 3> resolution{};
  // Coarsen by a few percent at a time until the vertex count fits (rounding up per axis
  // may overshoot a single cube-root step).
  for (int attempt = 0; attempt < 4096; ++attempt) {
    for (int a = 0; a < 3; ++a) {
      const double cells = std::ceil(double(extent[a]) / double(cell) - 1e-6);
      resolution[a] =
          uint32_t(std::clamp(cells, double(kMinGridResolution), double(kMaxGridResolution)));
    }
    if (product(resolution) <= max_vertices)
      return make_grid_layout(bounds_min, bounds_max, resolution);
    cell *= 1.02f;
  }
  throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
              "no grid resolution fits " + std::to_string(max_vertices) + " vertices");
}

}  // namespace bakegi
