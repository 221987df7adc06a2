// bakegi_web_* and the grid's stream helpers: what the web page and `bakegi serve` need
// (native/src/web/).
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <optional>

#include "api/api_guard.h"
#include "api/handles.h"
#include "grid/grid_file.h"
#include "grid/grid_quantization.h"
#include "grid/grid_visibility_volume.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "util/file_bytes.h"
#include "util/sampling.h"
#include "web/corner_grid_reach.h"
#include "web/gltf_export.h"
#include "web/grid_stream_order.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

namespace {

// The scene flattened for rays only; none for one build_scene refuses (no triangles). Its
// light is never read: a scene exported without its lamps (refused for having no light) is
// built again under a white world, copied only then.
std::optional<bakegi::Scene> scene_for_rays(const bakegi::SceneDescription& description) {
  const auto refused = [](const Error& e) { return e.status() == BAKEGI_ERROR_INVALID_SCENE; };
  try {
    return bakegi::build_scene(description);
  } catch (const Error& e) {
    if (!refused(e)) throw;
  }
  bakegi::SceneDescription lit = description;
  lit.world_radiance = glm::vec3(1.0f);
  try {
    return bakegi::build_scene(lit);
  } catch (const Error& e) {
    if (!refused(e)) throw;
  }
  return std::nullopt;
}

}  // namespace

extern "C" {

bakegi_status bakegi_web_export(const bakegi_scene* scene, const bakegi_grid* grid,
                                const char* folder, const float* camera) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(folder, "folder");
    bakegi::WebExportOptions options;
    if (camera) {
      for (int i = 0; i < 9; ++i) {
        if (!std::isfinite(camera[i])) {
          throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "camera values must be finite");
        }
      }
      options.has_camera = true;
      options.camera.position = {camera[0], camera[1], camera[2]};
      options.camera.rotation = {camera[3], camera[4], camera[5], camera[6]};
      options.camera.yfov = camera[7];
      options.camera.aspect = camera[8];
      if (!(options.camera.yfov > 0.0f && options.camera.yfov < 3.14159f) ||
          !(options.camera.aspect > 0.0f)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "camera: yfov must lie in (0, pi) and the aspect ratio be positive");
      }
    }
    const std::filesystem::path root = bakegi::utf8_path(folder);
    std::error_code error;
    std::filesystem::create_directories(root, error);
    if (error) {
      throw Error(BAKEGI_ERROR_IO,
                  "cannot make the folder " + std::string(folder) + ": " + error.message());
    }
    if (grid) {
      options.grid_file = "grid.bgivg";
      const bakegi::IrradianceVectorGrid page_grid = bakegi::grid_with_emitted_light(grid_of(grid));
      options.grid_has_emitted_light = grid_of(grid).has_emitted();
      const std::vector<uint8_t> bytes =
          bakegi::encode_grid_file(page_grid, bakegi::GridEncoding::kQuantized, grid->info_json);
      bakegi::write_file_atomically(root / options.grid_file, bytes);
      // What each place sees of the grid, so that the page does not read through walls.
      const uint32_t subdivision = bakegi::page_visibility_subdivision(page_grid.layout);
      const size_t subvoxels =
          page_grid.layout.vertex_count() * subdivision * subdivision * subdivision;
      std::optional<bakegi::Scene> built;
      if (subvoxels <= bakegi::kMaxVisibilitySubvoxels) {
        built = scene_for_rays(scene->description);
      } else {
        options.grid_too_large_for_visibility = true;
      }
      if (built) {
        const bakegi::RayTracer tracer(*built);
        const bakegi::GridVisibilityVolume volume = bakegi::build_grid_visibility_volume(
            page_grid, *built, tracer, subdivision,
            bakegi::max_component(scene->description.world_radiance) > 0.0f);
        options.grid_visibility_file = "grid_visibility.bin";
        bakegi::write_file_atomically(root / options.grid_visibility_file,
                                      bakegi::encode_visibility_file(volume, page_grid.layout));
        // Corners the volume's reading one subvoxel out cannot judge: pressed against or
        // buried under geometry.
        options.corner_reads_grid = bakegi::corners_reading_grid(page_grid, *built, tracer);
      }
    }
    const bakegi::WebGltf gltf = bakegi::encode_web_gltf(scene->description, options);
    bakegi::write_file_atomically(root / "scene.bin", gltf.bin);
    for (const auto& [name, png] : gltf.images) bakegi::write_file_atomically(root / name, png);
    bakegi::write_file_atomically(
        root / "scene.gltf",
        std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(gltf.json.data()),
                                 gltf.json.size()));
  });
}

bakegi_status bakegi_grid_stream_order(const bakegi_grid* grid, uint64_t seed,
                                       uint32_t* out_order) {
  return guarded(__func__, [&] {
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    require(out_order, "out_order");
    const std::vector<uint32_t> order = bakegi::grid_stream_order(g.layout, seed);
    std::copy(order.begin(), order.end(), out_order);
  });
}

bakegi_status bakegi_grid_encode_vertices(const bakegi_grid* grid, const uint32_t* vertices,
                                          uint64_t count, int encoding, uint8_t* out_bytes) {
  return guarded(__func__, [&] {
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    if (count == 0) return;
    require(vertices, "vertices");
    require(out_bytes, "out_bytes");
    if (encoding != BAKEGI_GRID_FACTORED && encoding != BAKEGI_GRID_QUANTIZED) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "vertices are sent factored (floats) or quantized, not encoding " +
                      std::to_string(encoding));
    }
    for (uint64_t i = 0; i < count; ++i) {
      if (vertices[i] >= g.layout.vertex_count()) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "vertex " + std::to_string(vertices[i]) + " is not in the grid");
      }
    }
    uint8_t* out = out_bytes;
    for (uint64_t i = 0; i < count; ++i) {
      for (int h = 0; h < 6; ++h) {
        const glm::mat3& m = g.at(vertices[i], h);
        if (encoding == BAKEGI_GRID_QUANTIZED) {
          const bakegi::QuantizedHemisphere q = bakegi::quantize_hemisphere(m, h);
          const uint8_t direction[3] = {q.direction.x, q.direction.y, q.direction.z};
          std::memcpy(out, direction, 3);
          std::memcpy(out + 3, &q.color, 4);  // little-endian, as the file
          out += 7;
        } else {
          const bakegi::FactoredHemisphere f = bakegi::factor_hemisphere(m, h);
          const float values[6] = {f.direction.x, f.direction.y, f.direction.z,
                                   f.color.x,     f.color.y,     f.color.z};
          std::memcpy(out, values, sizeof(values));
          out += sizeof(values);
        }
      }
    }
  });
}

}  // extern "C"
