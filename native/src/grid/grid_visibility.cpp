#include "grid/grid_visibility.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/error.h"

namespace bakegi {

namespace {

// The 4 x 4 x 4 vertices around p that `sees` accepts, weighted by inverse squared distance;
// nullopt when it accepts none.
std::optional<glm::vec3> widened_lookup(const IrradianceVectorGrid& grid, const glm::vec3& p,
                                        const glm::vec3& n, GridDirectionalWeights weights,
                                        const VertexFilter& sees) {
  const GridLayout& layout = grid.layout;
  const glm::vec3 g = layout.grid_coordinates(p);
  int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const int64_t last = int64_t(layout.resolution[a]) - 1;
    const float x = std::isfinite(g[a]) ? std::clamp(g[a], 0.0f, float(last)) : 0.0f;
    lo[a] = std::max<int64_t>(0, int64_t(std::floor(x)) - 1);
    hi[a] = std::min<int64_t>(last, int64_t(std::floor(x)) + 2);
  }
  size_t vertices[64];
  float spatial[64];
  size_t count = 0;
  float total = 0.0f;
  const glm::vec3 cell = layout.cell_size();
  for (int64_t k = lo[2]; k <= hi[2]; ++k) {
    for (int64_t j = lo[1]; j <= hi[1]; ++j) {
      for (int64_t i = lo[0]; i <= hi[0]; ++i) {
        const glm::vec3 at = layout.vertex_position(uint32_t(i), uint32_t(j), uint32_t(k));
        const size_t v = layout.vertex_index(uint32_t(i), uint32_t(j), uint32_t(k));
        if (!sees(v, at)) continue;
        const glm::vec3 d = (at - p) / cell;  // in cells, so the weights do not depend on units
        vertices[count] = v;
        spatial[count] = 1.0f / (glm::dot(d, d) + 0.25f);
        total += spatial[count++];
      }
    }
  }
  if (count == 0) return std::nullopt;
  for (size_t i = 0; i < count; ++i) spatial[i] /= total;
  return blend_vertices(grid, n, std::span<const size_t>(vertices, count),
                        std::span<const float>(spatial, count), weights);
}

}  // namespace

void evaluate_grid_in_scene(const IrradianceVectorGrid& grid, const Scene& scene,
                            const RayTracer& tracer, std::span<const glm::vec3> positions,
                            std::span<const glm::vec3> normals, const GridSceneLookup& lookup,
                            std::span<glm::vec3> out, std::span<uint8_t> unsure,
                            GridSceneStatistics& statistics) {
  const size_t count = positions.size();
  if (normals.size() != count || out.size() != count ||
      (!unsure.empty() && unsure.size() != count)) {
    throw Error(BAKEGI_ERROR_INTERNAL, "grid evaluation: sizes of the point arrays differ");
  }
  std::vector<uint8_t> buried;
  if (lookup.darken_buried && count > 0) {
    const std::vector<glm::vec3> p(positions.begin(), positions.end());
    std::vector<glm::vec3> n(normals.begin(), normals.end());
    for (glm::vec3& each : n) {
      const float length = glm::length(each);
      each = length > 0.0f && std::isfinite(length) ? each / length : glm::vec3(0, 0, 1);
    }
    buried = flag_samples_inside_geometry(scene, tracer, p, n, n, lookup.buried);
    statistics.rays += uint64_t(count) * lookup.buried.rays;
  }
  // Rays leave this far off the point's surface (and stop as far short of the vertex).
  const float lift = 1e-4f * std::max(scene.extent(), 1e-3f);
  const glm::vec3 cell = grid.layout.cell_size();
  const float half_cell = 0.5f * std::max({cell.x, cell.y, cell.z});
  std::atomic<uint64_t> rays{0}, unsure_count{0}, buried_count{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& block) {
        uint64_t block_rays = 0, block_unsure = 0, block_buried = 0;
        for (size_t i = block.begin(); i != block.end(); ++i) {
          if (!buried.empty() && buried[i]) {
            out[i] = glm::vec3(0.0f);
            if (!unsure.empty()) unsure[i] = kGridPointBuried;
            ++block_buried;
            continue;
          }
          const float length = glm::length(normals[i]);
          const glm::vec3 n = length > 0.0f ? normals[i] / length : glm::vec3(0.0f);
          const glm::vec3 origin = positions[i] + lift * n;
          const VertexFilter sees = [&](size_t vertex, const glm::vec3& at) {
            if (!grid.valid[vertex]) return false;
            const glm::vec3 to = at - origin;
            // Behind the point's own surface by more than half a cell: the other side's light.
            if (glm::dot(to, n) < -half_cell) return false;
            const float distance = glm::length(to);
            if (!(distance > 2.0f * lift)) return true;
            ++block_rays;
            return !tracer.occluded(Ray{origin, to / distance, 0.0f, distance - lift});
          };
          bool refused = false;
          out[i] = evaluate_grid(grid, positions[i], normals[i], lookup.interpolation,
                                 lookup.weights, lookup.visibility ? &sees : nullptr, &refused);
          if (refused) {
            // None of its own vertices: those a cell further out that it sees, by inverse
            // squared distance; none of those either (a face outside the rooms, a closed
            // nook): 0, unsure.
            const std::optional<glm::vec3> wider =
                widened_lookup(grid, positions[i], n, lookup.weights, sees);
            out[i] = wider ? *wider : glm::vec3(0.0f);
            refused = !wider;
          }
          if (!unsure.empty()) unsure[i] = refused ? kGridPointUnsure : kGridPointRead;
          block_unsure += refused;
        }
        rays.fetch_add(block_rays, std::memory_order_relaxed);
        unsure_count.fetch_add(block_unsure, std::memory_order_relaxed);
        buried_count.fetch_add(block_buried, std::memory_order_relaxed);
      });
  statistics.rays += rays.load();
  statistics.unsure += unsure_count.load();
  statistics.buried += buried_count.load();
}

}  // namespace bakegi
