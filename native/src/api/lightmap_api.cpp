// bakegi_lightmaps_*: the C boundary of lightmap/lightmap_set.h (texels as bake points,
// baked values resolved into images, in memory or as EXR files); see the lightmaps section
// of bakegi.h for the order of calls.
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "api/api_guard.h"
#include "api/handles.h"
#include "lightmap/exr_writer.h"
#include "lightmap/lightmap_layout_file.h"
#include "lightmap/lightmap_set.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

struct bakegi_lightmaps {
  bakegi::LightmapSet set;
};

namespace {

const bakegi::Mesh& mesh_at(const bakegi_scene* scene, uint32_t mesh) {
  const auto& meshes = scene->description.meshes;
  if (mesh >= meshes.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "mesh " + std::to_string(mesh) +
                                                   " does not exist (the scene has " +
                                                   std::to_string(meshes.size()) + ")");
  }
  return meshes[mesh];
}

bakegi::ExrWriteOptions exr_options(int full_float, uint32_t compression) {
  if (full_float != 0 && full_float != 1) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "full_float must be 0 or 1");
  }
  bakegi::ExrWriteOptions options;
  options.pixel_type = full_float ? bakegi::ExrPixelType::kFloat : bakegi::ExrPixelType::kHalf;
  switch (compression) {
    case BAKEGI_EXR_ZIP:
      options.compression = bakegi::ExrCompression::kZip;
      break;
    case BAKEGI_EXR_PIZ:
      options.compression = bakegi::ExrCompression::kPiz;
      break;
    case BAKEGI_EXR_NONE:
      options.compression = bakegi::ExrCompression::kNone;
      break;
    default:
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "compression " + std::to_string(compression) +
                                                     " is not a bakegi_exr_compression");
  }
  return options;
}

}  // namespace

extern "C" {

bakegi_status bakegi_lightmaps_create(bakegi_lightmaps** out_lightmaps) {
  return guarded(__func__, [&] {
    require(out_lightmaps, "out_lightmaps");
    *out_lightmaps = bakegi::give_out(std::make_unique<bakegi_lightmaps>());
  });
}

bakegi_status bakegi_lightmaps_set_memory_budget(bakegi_lightmaps* lightmaps, uint64_t megabytes) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    lightmaps->set.set_sample_budget_megabytes(megabytes);
  });
}

bakegi_status bakegi_lightmaps_cancel(bakegi_lightmaps* lightmaps) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    lightmaps->set.cancel();
  });
}

void bakegi_lightmaps_destroy(bakegi_lightmaps* lightmaps) {
  bakegi::destroy_handle(lightmaps);
}

bakegi_status bakegi_lightmaps_add(bakegi_lightmaps* lightmaps, const bakegi_scene* scene,
                                   uint32_t mesh, const float* lightmap_uvs, uint32_t width,
                                   uint32_t height, uint32_t* out_lightmap) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(scene, "scene");
    require(lightmap_uvs, "lightmap_uvs");
    const uint32_t index = lightmaps->set.add(mesh_at(scene, mesh), lightmap_uvs, width, height);
    if (out_lightmap) *out_lightmap = index;
  });
}

bakegi_status bakegi_lightmaps_add_to(bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                      const bakegi_scene* scene, uint32_t mesh,
                                      const float* lightmap_uvs) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(scene, "scene");
    require(lightmap_uvs, "lightmap_uvs");
    lightmaps->set.add_to(lightmap, mesh_at(scene, mesh), lightmap_uvs);
  });
}

bakegi_status bakegi_lightmaps_reject_inside(bakegi_lightmaps* lightmaps, const bakegi_scene* scene,
                                             uint32_t rays, float backface_fraction,
                                             float max_distance, uint64_t* out_rejected) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(scene, "scene");
    bakegi::BackfaceRejectionOptions options;
    if (rays != 0) options.rays = rays;
    if (backface_fraction != 0) options.backface_fraction = backface_fraction;
    options.max_distance = max_distance;
    const uint64_t rejected = lightmaps->set.reject_inside(scene->description, options);
    if (out_rejected) *out_rejected = rejected;
  });
}

uint32_t bakegi_lightmaps_count(const bakegi_lightmaps* lightmaps) {
  return bakegi::live(lightmaps) ? uint32_t(lightmaps->set.layout().lightmaps.size()) : 0;
}

bakegi_status bakegi_lightmaps_get_info(const bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                        bakegi_lightmap_info* out_info) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(out_info, "out_info");
    const bakegi::LightmapLayout::Lightmap& l = lightmaps->set.lightmap(lightmap);
    bakegi_lightmap_info info{};
    info.width = l.samples.width;
    info.height = l.samples.height;
    info.first_point = lightmaps->set.layout().first_point(lightmap);
    info.point_count = l.samples.size();
    info.covered_texels = l.samples.covered_texels();
    info.rejected_samples = l.rejected_samples;
    info.skipped_triangles =
        l.samples.skipped_degenerate_uv + l.samples.skipped_degenerate_geometry;
    *out_info = info;
  });
}

bakegi_status bakegi_lightmaps_get_points(const bakegi_lightmaps* lightmaps,
                                          bakegi_points** out_points) {
  return guarded(__func__, [&] {
    require(out_points, "out_points");
    *out_points = nullptr;
    require(lightmaps, "lightmaps");
    auto handle = std::make_unique<bakegi_points>();
    handle->points = lightmaps->set.points();
    *out_points = bakegi::give_out(std::move(handle));
  });
}

bakegi_status bakegi_lightmaps_write_exr(const bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                         const float* rgb, uint64_t count, const char* path,
                                         uint32_t padding, int full_float, uint32_t compression) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(rgb, "rgb");
    require(path, "path");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    bakegi::ExrWriteOptions options = exr_options(full_float, compression);
    options.cancel = lightmaps->set.cancel_flag();
    bakegi::write_exr(path, lightmaps->set.resolve(lightmap, rgb, count, padding), options);
  });
}

bakegi_status bakegi_lightmaps_resolve(const bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                       const float* rgb, uint64_t count, uint32_t padding,
                                       uint32_t channels, float* out_pixels, uint64_t capacity) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(rgb, "rgb");
    require(out_pixels, "out_pixels");
    if (channels != 3 && channels != 4) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "channels must be 3 (RGB) or 4 (RGBA), got " + std::to_string(channels));
    }
    const bakegi::LightmapLayout::Lightmap& l = lightmaps->set.lightmap(lightmap);
    const uint64_t needed = uint64_t(l.samples.width) * l.samples.height * channels;
    if (capacity < needed) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "out_pixels holds " + std::to_string(capacity) + " floats; lightmap " +
                      std::to_string(lightmap) + " needs " + std::to_string(needed));
    }
    const bakegi::RgbImage image = lightmaps->set.resolve(lightmap, rgb, count, padding);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      float* out = out_pixels + channels * i;
      out[0] = image.pixels[i].x;
      out[1] = image.pixels[i].y;
      out[2] = image.pixels[i].z;
      if (channels == 4) out[3] = 1.0f;
    }
  });
}

bakegi_status bakegi_lightmaps_write_file(const bakegi_lightmaps* lightmaps, const char* path) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(path, "path");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    bakegi::write_lightmap_layout_file(path, lightmaps->set.layout());
  });
}

bakegi_status bakegi_lightmaps_read_file(const char* path, bakegi_lightmaps** out_lightmaps) {
  return guarded(__func__, [&] {
    require(out_lightmaps, "out_lightmaps");
    *out_lightmaps = nullptr;
    require(path, "path");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    auto handle = std::make_unique<bakegi_lightmaps>();
    handle->set = bakegi::LightmapSet(bakegi::read_lightmap_layout_file(path));
    *out_lightmaps = bakegi::give_out(std::move(handle));
  });
}

}  // extern "C"
