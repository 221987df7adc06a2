#include "solvers/grid/grid_solver.h"

#include "grid/grid_field.h"
#include "grid/grid_file.h"
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
  return std::make_unique<GridField>(std::move(file.grid), settings.lookup, inputs.scene,
                                     inputs.tracer);
}

}  // namespace bakegi
