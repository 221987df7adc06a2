// `bakegi bake ... --lightmaps layout.bgl --exr-dir DIR`: the lightmap EXRs of a scene file
// whose bake points came from a lightmap layout (bakegi_lightmaps_get_points; the add-on's
// bakegi.export_scene_file(target='LIGHTMAP') writes the .bgs and .bgl pair). The layout
// is read and checked against the scene file's points before the bake, so that a wrong
// pair fails at once, not after a long bake.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "arguments.h"
#include "core_handles.h"

namespace bakegi::cli {

struct LightmapsDeleter {
  void operator()(bakegi_lightmaps* l) const { bakegi_lightmaps_destroy(l); }
};
using LightmapsHandle = std::unique_ptr<bakegi_lightmaps, LightmapsDeleter>;

struct LightmapOutput {
  std::string layout_path;                // --lightmaps
  std::string exr_dir;                    // --exr-dir: DIR/lightmap_<i>.exr for lightmap i
  uint32_t padding = 4;                   // --padding: texels of dilation around the charts
  bool full_float = false;                // --float: 32-bit floats instead of half
  uint32_t compression = BAKEGI_EXR_ZIP;  // --compression zip|piz|none
};

// The options above, for the bake command to add to its own.
std::vector<OptionSpec> lightmap_output_options();
// Reads them: nullopt when none is given; throws UsageError when --lightmaps and --exr-dir
// do not come together, or --padding/--float/--compression come without them.
std::optional<LightmapOutput> lightmap_output_from(const Arguments& args);

// Reads the layout (CoreError naming the path on failure) and checks that `points`, the
// scene file's bake points, are its points: the same count, then the same positions
// (FileError naming both files otherwise). Creates the EXR folder if it does not exist.
LightmapsHandle prepare_lightmap_output(const LightmapOutput& output, const std::string& scene_path,
                                        const bakegi_points* points);

// Writes every lightmap's EXR from the bake result (RGB per point, all points) and prints
// one line per file on stderr (stdout keeps the bake's JSON report).
void write_lightmap_exrs(const bakegi_lightmaps* lightmaps, const LightmapOutput& output,
                         const std::vector<float>& values);

}  // namespace bakegi::cli
