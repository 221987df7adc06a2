// bakegi_grid_*: Irradiance Vector Grids (native/src/grid/) behind the C API.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>

#include "api/api_guard.h"
#include "api/handles.h"
#include "api/text_output.h"
#include "grid/grid_file.h"
#include "grid/grid_interpolation.h"
#include "grid/grid_visibility.h"
#include "grid/grid_visibility_volume.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "util/file_bytes.h"
#include "util/sampling.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

namespace {

constexpr uint64_t kDefaultMaxVertices = uint64_t(64) * 64 * 64;
constexpr uint32_t kDefaultRaysPerHemisphere = 64;

glm::vec3 vec3_from(const float* v) {
  return {v[0], v[1], v[2]};
}

static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
const glm::vec3* as_vec3(const float* xyz) {
  return reinterpret_cast<const glm::vec3*>(xyz);
}

void check_lookup(int interpolation, int directional) {
  if (interpolation != BAKEGI_GRID_TRILINEAR && interpolation != BAKEGI_GRID_TRICUBIC) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "unknown interpolation " + std::to_string(interpolation));
  }
  if (directional != BAKEGI_GRID_SQUARED && directional != BAKEGI_GRID_ABSOLUTE) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "unknown directional weights " + std::to_string(directional));
  }
}

void check_count(uint64_t count) {
  if (count > (uint64_t(1) << 40)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "count " + std::to_string(count) + " is absurd");
  }
}

}  // namespace

extern "C" {

bakegi_status bakegi_grid_create(const float bounds_min[3], const float bounds_max[3],
                                 float cell_size, uint64_t max_vertices, bakegi_grid** out_grid) {
  return guarded(__func__, [&] {
    require(out_grid, "out_grid");
    *out_grid = nullptr;
    require(bounds_min, "bounds_min");
    require(bounds_max, "bounds_max");
    const bakegi::GridLayout layout =
        bakegi::choose_grid_layout(vec3_from(bounds_min), vec3_from(bounds_max), cell_size,
                                   max_vertices == 0 ? kDefaultMaxVertices : max_vertices);
    auto handle = std::make_unique<bakegi_grid>();
    handle->grid = std::make_shared<const bakegi::IrradianceVectorGrid>(layout);
    *out_grid = bakegi::give_out(std::move(handle));
  });
}

void bakegi_grid_destroy(bakegi_grid* grid) {
  bakegi::destroy_handle(grid);
}

bakegi_status bakegi_grid_get_info(const bakegi_grid* grid, bakegi_grid_info* out_info) {
  return guarded(__func__, [&] {
    require(out_info, "out_info");
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    bakegi_grid_info info{};
    for (int a = 0; a < 3; ++a) {
      info.bounds_min[a] = g.layout.bounds_min[a];
      info.bounds_max[a] = g.layout.bounds_max[a];
      info.resolution[a] = g.layout.resolution[a];
    }
    info.vertex_count = g.vertex_count();
    info.invalid_vertices = uint64_t(std::count(g.valid.begin(), g.valid.end(), uint8_t(0)));
    *out_info = info;
  });
}

bakegi_status bakegi_job_start_grid(const bakegi_scene* scene, const bakegi_grid* layout,
                                    uint32_t rays_per_hemisphere, const bakegi_settings* settings,
                                    bakegi_job** out_job) {
  return guarded(__func__, [&] {
    require(out_job, "out_job");
    *out_job = nullptr;
    require(scene, "scene");
    bakegi::GridRequest request;
    request.layout = grid_of(layout).layout;
    request.gather.rays_per_hemisphere =
        rays_per_hemisphere == 0 ? kDefaultRaysPerHemisphere : rays_per_hemisphere;
    if (request.gather.rays_per_hemisphere > 65536) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "rays_per_hemisphere must be in [1, 65536] (0 = 64), got " +
                      std::to_string(rays_per_hemisphere));
    }
    auto handle = std::make_unique<bakegi_job>();
    handle->job = std::make_unique<bakegi::BakeJob>(
        scene->description, request, settings ? settings->settings : bakegi::Settings());
    *out_job = bakegi::give_out(std::move(handle));
  });
}

bakegi_status bakegi_job_get_grid(const bakegi_job* job, bakegi_grid** out_grid) {
  return guarded(__func__, [&] {
    require(out_grid, "out_grid");
    *out_grid = nullptr;
    require(job, "job");
    require(job->job.get(), "job");
    if (!job->job->is_done()) throw Error(BAKEGI_ERROR_NOT_READY, "the job has not finished yet");
    std::shared_ptr<const bakegi::IrradianceVectorGrid> grid = job->job->grid();
    if (!grid) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "the job has no grid (not a grid bake, or it failed or was cancelled)");
    }
    auto handle = std::make_unique<bakegi_grid>();
    handle->grid = std::move(grid);
    *out_grid = bakegi::give_out(std::move(handle));
  });
}

bakegi_status bakegi_grid_evaluate(const bakegi_grid* grid, const float* positions,
                                   const float* normals, uint64_t count, int interpolation,
                                   int directional, float* out_rgb) {
  return guarded(__func__, [&] {
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    check_lookup(interpolation, directional);
    if (count == 0) return;
    require(positions, "positions");
    require(normals, "normals");
    require(out_rgb, "out_rgb");
    check_count(count);
    auto* out = reinterpret_cast<glm::vec3*>(out_rgb);
    bakegi::evaluate_grid(
        g, std::span<const glm::vec3>(as_vec3(positions), count),
        std::span<const glm::vec3>(as_vec3(normals), count), std::span<glm::vec3>(out, count),
        bakegi::GridInterpolation(interpolation), bakegi::GridDirectionalWeights(directional));
  });
}

bakegi_status bakegi_grid_evaluate_in_scene(const bakegi_grid* grid, const bakegi_scene* scene,
                                            const float* positions, const float* normals,
                                            uint64_t count, int interpolation, int directional,
                                            uint32_t flags, float* out_rgb, uint8_t* out_codes) {
  return guarded(__func__, [&] {
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    require(scene, "scene");
    check_lookup(interpolation, directional);
    if (flags & ~uint32_t(BAKEGI_GRID_VISIBILITY | BAKEGI_GRID_DARKEN_BURIED |
                          BAKEGI_GRID_PAGE_VISIBILITY)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "unknown flags " + std::to_string(flags));
    }
    if ((flags & BAKEGI_GRID_PAGE_VISIBILITY) &&
        (flags != BAKEGI_GRID_PAGE_VISIBILITY || interpolation != BAKEGI_GRID_TRILINEAR)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "the page's visibility is read alone (no other flag), trilinearly");
    }
    if (count == 0) return;
    require(positions, "positions");
    require(normals, "normals");
    require(out_rgb, "out_rgb");
    check_count(count);
    const bakegi::Scene built = bakegi::build_scene(scene->description);
    const bakegi::RayTracer tracer(built);
    if (flags & BAKEGI_GRID_PAGE_VISIBILITY) {
      const bakegi::GridVisibilityVolume volume = bakegi::build_grid_visibility_volume(
          g, built, tracer, bakegi::page_visibility_subdivision(g.layout),
          bakegi::max_component(built.description.world_radiance) > 0.0f);
      bakegi::evaluate_grid_with_volume(
          g, volume, std::span<const glm::vec3>(as_vec3(positions), count),
          std::span<const glm::vec3>(as_vec3(normals), count),
          bakegi::GridDirectionalWeights(directional),
          std::span<glm::vec3>(reinterpret_cast<glm::vec3*>(out_rgb), count),
          out_codes ? std::span<uint8_t>(out_codes, count) : std::span<uint8_t>());
      // And, as the page's vertices carry it (web/corner_grid_reach.h), 0 where Apply Grid's
      // rays read nothing: the point sees no grid vertex or lies buried.
      std::vector<glm::vec3> rays(count);
      std::vector<uint8_t> codes(count, bakegi::kGridPointRead);
      bakegi::GridSceneStatistics statistics;
      bakegi::evaluate_grid_in_scene(g, built, tracer,
                                     std::span<const glm::vec3>(as_vec3(positions), count),
                                     std::span<const glm::vec3>(as_vec3(normals), count),
                                     bakegi::GridSceneLookup{}, rays, codes, statistics);
      for (size_t i = 0; i < count; ++i) {
        if (codes[i] == bakegi::kGridPointRead) continue;
        std::fill_n(out_rgb + 3 * i, 3, 0.0f);
        if (out_codes && out_codes[i] == bakegi::kGridPointRead) out_codes[i] = codes[i];
      }
      return;
    }
    bakegi::GridSceneLookup lookup;
    lookup.interpolation = bakegi::GridInterpolation(interpolation);
    lookup.weights = bakegi::GridDirectionalWeights(directional);
    lookup.visibility = (flags & BAKEGI_GRID_VISIBILITY) != 0;
    lookup.darken_buried = (flags & BAKEGI_GRID_DARKEN_BURIED) != 0;
    bakegi::GridSceneStatistics statistics;
    bakegi::evaluate_grid_in_scene(
        g, built, tracer, std::span<const glm::vec3>(as_vec3(positions), count),
        std::span<const glm::vec3>(as_vec3(normals), count), lookup,
        std::span<glm::vec3>(reinterpret_cast<glm::vec3*>(out_rgb), count),
        out_codes ? std::span<uint8_t>(out_codes, count) : std::span<uint8_t>(), statistics);
  });
}

bakegi_status bakegi_grid_write_file(const bakegi_grid* grid, const char* path, int encoding,
                                     const char* info_json) {
  return guarded(__func__, [&] {
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    require(path, "path");
    if (encoding != BAKEGI_GRID_FLOAT && encoding != BAKEGI_GRID_QUANTIZED &&
        encoding != BAKEGI_GRID_FACTORED) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "unknown encoding " + std::to_string(encoding));
    }
    const std::vector<uint8_t> bytes = bakegi::encode_grid_file(
        g, bakegi::GridEncoding(encoding), info_json ? std::string(info_json) : grid->info_json);
    bakegi::write_file_atomically(bakegi::utf8_path(path), bytes);
  });
}

bakegi_status bakegi_grid_read_file(const char* path, bakegi_grid** out_grid) {
  return guarded(__func__, [&] {
    require(out_grid, "out_grid");
    *out_grid = nullptr;
    require(path, "path");
    const std::vector<uint8_t> bytes =
        bakegi::read_file_bytes(bakegi::utf8_path(path), bakegi::kMaxGridFileBytes);
    bakegi::GridFile file = bakegi::decode_grid_file(bytes, path);
    auto handle = std::make_unique<bakegi_grid>();
    handle->grid = std::make_shared<const bakegi::IrradianceVectorGrid>(std::move(file.grid));
    handle->info_json = std::move(file.info_json);
    *out_grid = bakegi::give_out(std::move(handle));
  });
}

bakegi_status bakegi_grid_with_emitted_light(const bakegi_grid* grid, bakegi_grid** out_grid,
                                             int* out_has_emitted) {
  return guarded(__func__, [&] {
    if (out_grid) *out_grid = nullptr;
    const bakegi::IrradianceVectorGrid& g = grid_of(grid);
    if (out_has_emitted) *out_has_emitted = g.has_emitted() ? 1 : 0;
    if (!out_grid) return;  // the question alone
    auto handle = std::make_unique<bakegi_grid>();
    handle->grid =
        std::make_shared<const bakegi::IrradianceVectorGrid>(bakegi::grid_with_emitted_light(g));
    handle->info_json = grid->info_json;
    *out_grid = bakegi::give_out(std::move(handle));
  });
}

bakegi_status bakegi_grid_get_info_json(const bakegi_grid* grid, char* buffer, size_t capacity,
                                        size_t* out_length) {
  return guarded(__func__, [&] {
    grid_of(grid);
    bakegi::check_text_output(buffer, capacity, out_length);
    bakegi::write_text_output(grid->info_json, buffer, capacity, out_length);
  });
}

}  // extern "C"
