#include "solvers/grid/grid_solver.h"

#include <algorithm>

#include "grid/grid_file.h"
#include "grid/grid_visibility.h"
#include "settings/settings.h"
#include "util/error.h"
#include "util/file_bytes.h"
#include "util/job_context.h"

namespace bakegi {

namespace {

using R = SettingRole;

struct GridMethodSettings {
  std::string file;
  GridSceneLookup lookup;

  static GridMethodSettings from(const Settings& settings) {
    const SettingReader read(settings, method_schema("grid"));
    GridMethodSettings s;
    s.file = read.get_string("grid_file");
    if (s.file.empty()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "method grid needs setting grid_file: the .bgivg file to read");
    }
    s.lookup.interpolation = read.get_string("grid_interpolation") == "tricubic"
                                 ? GridInterpolation::kTricubic
                                 : GridInterpolation::kTrilinear;
    s.lookup.weights = read.get_string("grid_directional") == "squared"
                           ? GridDirectionalWeights::kSquared
                           : GridDirectionalWeights::kAbsolute;
    s.lookup.visibility = read.get_int("grid_visibility") != 0;
    s.lookup.darken_buried = read.get_int("grid_darken_buried") != 0;
    return s;
  }
};

// Points per call to the grid's (parallel) reading, between progress reports and cancel.
constexpr size_t kChunk = 1 << 16;

class BakedGridField : public IndirectField {
 public:
  BakedGridField(IrradianceVectorGrid grid, const GridSceneLookup& lookup, const Scene& scene,
                 const RayTracer& tracer)
      : grid_(std::move(grid)), lookup_(lookup), scene_(scene), tracer_(tracer) {}

  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override {
    GridSceneStatistics statistics;
    std::vector<uint8_t> codes(points.size());
    for (size_t first = 0; first < points.size(); first += kChunk) {
      context.throw_if_cancelled();
      const size_t count = std::min(kChunk, points.size() - first);
      evaluate_grid_in_scene(grid_, scene_, tracer_,
                             std::span<const glm::vec3>(points.positions).subspan(first, count),
                             std::span<const glm::vec3>(points.normals).subspan(first, count),
                             lookup_, out.subspan(first, count),
                             std::span<uint8_t>(codes).subspan(first, count), statistics);
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

 private:
  IrradianceVectorGrid grid_;
  GridSceneLookup lookup_;
  const Scene& scene_;
  const RayTracer& tracer_;
};

}  // namespace

const std::vector<SettingSpec>& GridSolver::setting_specs() {
  static const std::vector<SettingSpec> specs = {
      text_setting("grid_file", "", {}, R::kLighting,
                   "the baked grid (.bgivg, UTF-8 path) whose light the bake reads"),
      text_setting("grid_interpolation", "trilinear", {"trilinear", "tricubic"}, R::kLighting,
                   "spatial interpolation between the grid's vertices (docs/ivg.md)"),
      text_setting("grid_directional", "absolute", {"absolute", "squared"}, R::kLighting,
                   "weights between the axis hemispheres: |n| (exact under uniform light) or "
                   "the paper's n^2"),
      integer_setting("grid_visibility", 1, 0, 1, R::kLighting,
                      "1: a point reads only the grid vertices it sees (no light through thin "
                      "walls); 0: the paper's reading"),
      integer_setting("grid_darken_buried", 1, 0, 1, R::kLighting,
                      "1: points inside or under other geometry read 0, as in a bake"),
  };
  return specs;
}

void GridSolver::check_settings(const Settings& settings) const {
  (void)GridMethodSettings::from(settings);
}

std::unique_ptr<IndirectField> GridSolver::solve(const SolveInputs& inputs, JobContext& context) {
  const GridMethodSettings settings = GridMethodSettings::from(inputs.settings);
  context.set_stage_text("reading the grid");
  const std::vector<uint8_t> bytes = read_file_bytes(utf8_path(settings.file), kMaxGridFileBytes);
  GridFile file = decode_grid_file(bytes, settings.file);
  return std::make_unique<BakedGridField>(std::move(file.grid), settings.lookup, inputs.scene,
                                          inputs.tracer);
}

}  // namespace bakegi
