#include "grid/grid_field.h"

#include <algorithm>
#include <string>
#include <vector>

#include "util/job_context.h"

namespace bakegi {

namespace {

// Points per call to the grid's (parallel) reading, between progress reports and cancel.
constexpr size_t kChunk = 1 << 16;

}  // namespace

void GridField::evaluate(const BakePoints& points, std::span<glm::vec3> out,
                         JobContext& context) const {
  GridSceneStatistics statistics;
  std::vector<uint8_t> codes(points.size());
  for (size_t first = 0; first < points.size(); first += kChunk) {
    context.throw_if_cancelled();
    const size_t count = std::min(kChunk, points.size() - first);
    evaluate_grid_in_scene(
        grid_, scene_, tracer_, std::span<const glm::vec3>(points.positions).subspan(first, count),
        std::span<const glm::vec3>(points.normals).subspan(first, count), lookup_,
        out.subspan(first, count), std::span<uint8_t>(codes).subspan(first, count), statistics);
    context.set_stage_progress(double(first + count) / double(points.size()));
  }
  context.report().add_count("rays", statistics.rays);
  context.report().add_count("grid_unsure_points", statistics.unsure);
  context.report().add_count("grid_buried_points", statistics.buried);
  if (statistics.unsure > 0) {
    context.report().warn(std::to_string(statistics.unsure) +
                          " points saw no grid vertex near them and read 0 (outside the "
                          "grid's rooms, or the grid is too coarse there)");
  }
}

}  // namespace bakegi
