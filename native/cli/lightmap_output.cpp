#include "lightmap_output.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "file_error.h"
#include "usage_error.h"

namespace bakegi::cli {

namespace {

constexpr uint32_t kMaxPadding = 1024;  // as bakegi_lightmaps_write_exr

uint32_t compression_from(const std::string& name) {
  if (name == "zip") return BAKEGI_EXR_ZIP;
  if (name == "piz") return BAKEGI_EXR_PIZ;
  if (name == "none") return BAKEGI_EXR_NONE;
  throw UsageError("--compression: '" + name + "' is not zip, piz or none");
}

std::string exr_path(const LightmapOutput& output, uint32_t lightmap) {
  return (std::filesystem::path(output.exr_dir) / ("lightmap_" + std::to_string(lightmap) + ".exr"))
      .string();
}

}  // namespace

std::vector<OptionSpec> lightmap_output_options() {
  return {{"lightmaps"}, {"exr-dir"}, {"padding"}, {"float", false}, {"compression"}};
}

std::optional<LightmapOutput> lightmap_output_from(const Arguments& args) {
  const bool layout = args.has("lightmaps"), folder = args.has("exr-dir");
  if (!layout && !folder) {
    for (const char* name : {"padding", "float", "compression"}) {
      if (args.has(name)) {
        throw UsageError(std::string("--") + name + " needs --lightmaps and --exr-dir");
      }
    }
    return std::nullopt;
  }
  if (!layout) throw UsageError("--exr-dir needs --lightmaps layout.bgl");
  if (!folder) throw UsageError("--lightmaps needs --exr-dir DIR (where the EXRs go)");
  LightmapOutput output;
  output.layout_path = *args.value("lightmaps");
  output.exr_dir = *args.value("exr-dir");
  output.padding = uint32_t(args.int_value("padding", output.padding, 0, kMaxPadding));
  output.full_float = args.has("float");
  if (const auto name = args.value("compression")) output.compression = compression_from(*name);
  return output;
}

LightmapsHandle prepare_lightmap_output(const LightmapOutput& output, const std::string& scene_path,
                                        const bakegi_points* points) {
  bakegi_lightmaps* raw = nullptr;
  check(bakegi_lightmaps_read_file(output.layout_path.c_str(), &raw),
        "reading " + output.layout_path);
  LightmapsHandle lightmaps(raw);

  const uint32_t count = bakegi_lightmaps_count(lightmaps.get());
  uint64_t layout_points = 0;
  for (uint32_t i = 0; i < count; ++i) {
    bakegi_lightmap_info info{};
    check(bakegi_lightmaps_get_info(lightmaps.get(), i, &info), "reading " + output.layout_path);
    layout_points += info.point_count;
  }
  const uint64_t scene_points = bakegi_points_count(points);
  const std::string pair = scene_path + " and " + output.layout_path;
  if (layout_points != scene_points) {
    throw FileError(pair + " do not belong together: the scene file has " +
                    std::to_string(scene_points) + " bake points, the layout's " +
                    std::to_string(count) + " lightmaps have " + std::to_string(layout_points) +
                    " (export both in one go)");
  }
  // Equal counts can still be another export's: compare the positions too. Both files
  // store the same float32 values, so they match exactly; the tolerance only forgives a
  // caller that recomputed them in double.
  bakegi_points* raw_points = nullptr;
  check(bakegi_lightmaps_get_points(lightmaps.get(), &raw_points), "reading " + output.layout_path);
  const PointsHandle layout(raw_points);
  std::vector<float> expected(3 * scene_points), actual(3 * scene_points);
  check(bakegi_points_get(layout.get(), expected.data(), nullptr, nullptr),
        "reading " + output.layout_path);
  check(bakegi_points_get(points, actual.data(), nullptr, nullptr), "reading " + scene_path);
  for (size_t i = 0; i < expected.size(); ++i) {
    if (!(std::abs(expected[i] - actual[i]) <= 1e-5f * (1.0f + std::abs(expected[i])))) {
      throw FileError(pair + " do not belong together: bake point " + std::to_string(i / 3) +
                      " lies elsewhere in the layout (export both in one go)");
    }
  }

  std::error_code error;
  std::filesystem::create_directories(output.exr_dir, error);
  if (!std::filesystem::is_directory(output.exr_dir)) {
    throw FileError(output.exr_dir + ": cannot create the folder" +
                    (error ? ": " + error.message() : std::string()));
  }
  return lightmaps;
}

void write_lightmap_exrs(const bakegi_lightmaps* lightmaps, const LightmapOutput& output,
                         const std::vector<float>& values) {
  const uint64_t point_count = values.size() / 3;
  for (uint32_t i = 0; i < bakegi_lightmaps_count(lightmaps); ++i) {
    const std::string path = exr_path(output, i);
    check(bakegi_lightmaps_write_exr(lightmaps, i, values.data(), point_count, path.c_str(),
                                     output.padding, output.full_float ? 1 : 0, output.compression),
          "writing " + path);
    bakegi_lightmap_info info{};
    check(bakegi_lightmaps_get_info(lightmaps, i, &info), "reading the lightmaps");
    std::error_code error;
    const auto bytes = std::filesystem::file_size(path, error);
    std::fprintf(stderr, "wrote %s: %u x %u texels, %llu covered, %llu bytes\n", path.c_str(),
                 info.width, info.height, static_cast<unsigned long long>(info.covered_texels),
                 static_cast<unsigned long long>(error ? 0 : bytes));
  }
}

}  // namespace bakegi::cli
