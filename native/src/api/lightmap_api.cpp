// bakegi_lightmaps_*: lightmap texels as bake points, and baked values as padded EXR files
// (see the lightmaps section of bakegi.h for the order of calls).
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "api/api_guard.h"
#include "api/handles.h"
#include "lightmap/backface_rejection.h"
#include "lightmap/lightmap_layout.h"
#include "lightmap/lightmap_layout_file.h"
#include "lightmap/lightmap_seams.h"
#include "lightmap/texel_rasterizer.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "lightmap/exr_writer.h"
#include "lightmap/lightmap_padding.h"
#include "lightmap/seam_stitching.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

using bakegi::kMaxLightmapSide;
using Lightmap = bakegi::LightmapLayout::Lightmap;

// What the texel samples of all lightmaps may take: the core's default memory budget unless
// bakegi_lightmaps_set_memory_budget gives the bake's.
constexpr uint64_t kDefaultSampleBudgetBytes = uint64_t(4096) << 20;

struct bakegi_lightmaps {
  bakegi::LightmapLayout layout;
  uint64_t sample_budget_bytes = kDefaultSampleBudgetBytes;
};

namespace {

constexpr uint32_t kMaxPadding = 1024;

// A sample costs 48 bytes here (position, normal, object id, face normal, texel, weight) and
// 28 more as a bake point of the job.
constexpr uint64_t kBytesPerSample = 48 + 28;

// Refuses, before anything is allocated, a mesh whose samples could take the lightmaps
// over the budget (an upper bound, so a refusal names the density, not a crash).
void check_sample_budget(uint64_t budget_bytes, uint64_t existing,
                         const std::vector<bakegi::LightmapTriangle>& triangles, uint32_t width,
                         uint32_t height) {
  const uint64_t bound = existing + bakegi::max_texel_samples(triangles, width, height);
  if (bound > budget_bytes / kBytesPerSample) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                "the lightmaps could need up to " + std::to_string(bound) + " texel samples (" +
                    std::to_string(bound * kBytesPerSample >> 20) + " MiB), more than the " +
                    std::to_string(budget_bytes >> 20) +
                    " MiB budget; lower the texel density or the lightmap size");
  }
}

Lightmap& lightmap_at(bakegi::LightmapLayout& layout, uint32_t index) {
  if (index >= layout.lightmaps.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap " + std::to_string(index) +
                                                   " does not exist (there are " +
                                                   std::to_string(layout.lightmaps.size()) + ")");
  }
  return layout.lightmaps[index];
}
const Lightmap& lightmap_at(const bakegi::LightmapLayout& layout, uint32_t index) {
  return lightmap_at(const_cast<bakegi::LightmapLayout&>(layout), index);
}

const bakegi::Mesh& mesh_at(const bakegi_scene* scene, uint32_t mesh) {
  const auto& meshes = scene->description.meshes;
  if (mesh >= meshes.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "mesh " + std::to_string(mesh) +
                                                   " does not exist (the scene has " +
                                                   std::to_string(meshes.size()) + ")");
  }
  return meshes[mesh];
}

// The mesh's triangles with the caller's lightmap UVs, as the rasterizer takes them.
std::vector<bakegi::LightmapTriangle> lightmap_triangles(const bakegi::Mesh& mesh,
                                                         const float* uvs) {
  const size_t triangle_count = mesh.indices.size() / 3;
  std::vector<bakegi::LightmapTriangle> triangles(triangle_count);
  for (size_t t = 0; t < triangle_count; ++t) {
    bakegi::LightmapTriangle& tri = triangles[t];
    for (int k = 0; k < 3; ++k) {
      const size_t corner = 3 * t + k;
      tri.p[k] = mesh.positions.at(mesh.indices[corner]);
      tri.n[k] = mesh.corner_normals.empty() ? glm::vec3(0.0f) : mesh.corner_normals[corner];
      tri.uv[k] = {uvs[2 * corner], uvs[2 * corner + 1]};
      if (!std::isfinite(tri.uv[k].x) || !std::isfinite(tri.uv[k].y)) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap_uvs: triangle " + std::to_string(t) +
                                                       " corner " + std::to_string(k) +
                                                       " is not finite");
      }
    }
  }
  return triangles;
}

}  // namespace

extern "C" {

bakegi_status bakegi_lightmaps_create(bakegi_lightmaps** out_lightmaps) {
  return guarded(__func__, [&] {
    require(out_lightmaps, "out_lightmaps");
    *out_lightmaps = new bakegi_lightmaps();
  });
}

bakegi_status bakegi_lightmaps_set_memory_budget(bakegi_lightmaps* lightmaps,
                                                uint64_t megabytes) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    if (megabytes < 1 || megabytes > (uint64_t(1) << 30)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "memory budget must be in [1, 1073741824] MB, got " + std::to_string(megabytes));
    }
    lightmaps->sample_budget_bytes = megabytes << 20;
  });
}

void bakegi_lightmaps_destroy(bakegi_lightmaps* lightmaps) {
  delete lightmaps;
}

bakegi_status bakegi_lightmaps_add(bakegi_lightmaps* lightmaps, const bakegi_scene* scene,
                                   uint32_t mesh, const float* lightmap_uvs, uint32_t width,
                                   uint32_t height, uint32_t* out_lightmap) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(scene, "scene");
    require(lightmap_uvs, "lightmap_uvs");
    const bakegi::Mesh& source = mesh_at(scene, mesh);
    if (width < 1 || height < 1 || width > kMaxLightmapSide || height > kMaxLightmapSide) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap size " + std::to_string(width) + " x " +
                                                     std::to_string(height) + " is not in 1.." +
                                                     std::to_string(kMaxLightmapSide));
    }
    const std::vector<bakegi::LightmapTriangle> triangles =
        lightmap_triangles(source, lightmap_uvs);
    check_sample_budget(lightmaps->sample_budget_bytes, lightmaps->layout.total_points(),
                        triangles, width, height);
    Lightmap lightmap;
    lightmap.samples = bakegi::rasterize_texels(triangles, width, height, source.object_id);
    lightmap.seams = bakegi::find_lightmap_seams(source.indices, triangles, width, height);
    lightmaps->layout.lightmaps.push_back(std::move(lightmap));
    if (out_lightmap) *out_lightmap = uint32_t(lightmaps->layout.lightmaps.size() - 1);
  });
}

bakegi_status bakegi_lightmaps_add_to(bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                      const bakegi_scene* scene, uint32_t mesh,
                                      const float* lightmap_uvs) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(scene, "scene");
    require(lightmap_uvs, "lightmap_uvs");
    if (lightmaps->layout.rejected_inside) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "bakegi_lightmaps_reject_inside has already run: samples added now would not "
                  "be checked (add every mesh first, then reject)");
    }
    Lightmap& target = lightmap_at(lightmaps->layout, lightmap);
    const bakegi::Mesh& source = mesh_at(scene, mesh);
    const std::vector<bakegi::LightmapTriangle> triangles =
        lightmap_triangles(source, lightmap_uvs);
    const uint32_t width = target.samples.width, height = target.samples.height;
    check_sample_budget(lightmaps->sample_budget_bytes, lightmaps->layout.total_points(),
                        triangles, width, height);
    bakegi::TexelSamples samples =
        bakegi::rasterize_texels(triangles, width, height, source.object_id);
    const std::vector<bakegi::LightmapSeam> seams =
        bakegi::find_lightmap_seams(source.indices, triangles, width, height);
    // Room first, so that nothing after the samples are appended can fail.
    target.seams.reserve(target.seams.size() + seams.size());
    bakegi::append_samples(target.samples, std::move(samples));
    target.seams.insert(target.seams.end(), seams.begin(), seams.end());
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
    const bakegi::Scene built = bakegi::build_scene(scene->description);
    const bakegi::RayTracer tracer(built);
    uint64_t rejected = 0;
    for (Lightmap& lightmap : lightmaps->layout.lightmaps) {
      bakegi::TexelSamples& samples = lightmap.samples;
      const std::vector<uint8_t> flags = bakegi::flag_samples_inside_geometry(
          built, tracer, samples.points.positions, samples.face_normals, samples.points.normals,
          options);
      // Samples are dropped from here on: refuse later additions even if this call then
      // fails (a call refused for its options above has changed nothing).
      lightmaps->layout.rejected_inside = true;
      std::vector<bool> keep(flags.size());
      uint64_t dropped = 0;
      for (size_t i = 0; i < flags.size(); ++i) {
        keep[i] = !flags[i];
        dropped += flags[i];
      }
      bakegi::keep_samples(samples, keep);
      lightmap.rejected_samples += dropped;
      rejected += dropped;
    }
    lightmaps->layout.rejected_inside = true;
    if (out_rejected) *out_rejected = rejected;
  });
}

uint32_t bakegi_lightmaps_count(const bakegi_lightmaps* lightmaps) {
  return lightmaps ? uint32_t(lightmaps->layout.lightmaps.size()) : 0;
}

bakegi_status bakegi_lightmaps_get_info(const bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                        bakegi_lightmap_info* out_info) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(out_info, "out_info");
    const Lightmap& l = lightmap_at(lightmaps->layout, lightmap);
    bakegi_lightmap_info info{};
    info.width = l.samples.width;
    info.height = l.samples.height;
    info.first_point = lightmaps->layout.first_point(lightmap);
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
    const uint64_t total = lightmaps->layout.total_points();
    if (total == 0) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "the lightmaps have no texel samples (no lightmap added, or no triangle "
                  "covers a texel)");
    }
    auto handle = std::make_unique<bakegi_points>();
    bakegi::BakePoints& points = handle->points;
    points.positions.reserve(total);
    points.normals.reserve(total);
    points.object_ids.reserve(total);
    for (const Lightmap& l : lightmaps->layout.lightmaps) {
      const bakegi::BakePoints& p = l.samples.points;
      points.positions.insert(points.positions.end(), p.positions.begin(), p.positions.end());
      points.normals.insert(points.normals.end(), p.normals.begin(), p.normals.end());
      points.object_ids.insert(points.object_ids.end(), p.object_ids.begin(), p.object_ids.end());
    }
    *out_points = handle.release();
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
    const Lightmap& l = lightmap_at(lightmaps->layout, lightmap);
    const uint64_t total = lightmaps->layout.total_points();
    if (count != total) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "count " + std::to_string(count) + " differs from the lightmaps' " +
                      std::to_string(total) + " points (pass the whole bake result)");
    }
    if (padding > kMaxPadding) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "padding " + std::to_string(padding) + " is over " + std::to_string(kMaxPadding));
    }
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
    const uint64_t first = lightmaps->layout.first_point(lightmap);
    std::vector<glm::vec3> values(l.samples.size());
    for (size_t i = 0; i < values.size(); ++i) {
      const float* v = rgb + 3 * (first + i);
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "rgb of point " + std::to_string(first + i) + " is not finite");
      }
      values[i] = {v[0], v[1], v[2]};
    }
    std::vector<uint8_t> filled;
    bakegi::RgbImage image = bakegi::resolve_texels(l.samples, values.data(), filled);
    bakegi::dilate_texels(image, filled, padding);
    bakegi::stitch_seams(image, l.samples.covered, filled, l.seams);
    bakegi::write_exr(path, image, options);
  });
}

bakegi_status bakegi_lightmaps_write_file(const bakegi_lightmaps* lightmaps, const char* path) {
  return guarded(__func__, [&] {
    require(lightmaps, "lightmaps");
    require(path, "path");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    bakegi::write_lightmap_layout_file(path, lightmaps->layout);
  });
}

bakegi_status bakegi_lightmaps_read_file(const char* path, bakegi_lightmaps** out_lightmaps) {
  return guarded(__func__, [&] {
    require(out_lightmaps, "out_lightmaps");
    *out_lightmaps = nullptr;
    require(path, "path");
    if (path[0] == '\0') throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "path is empty");
    auto handle = std::make_unique<bakegi_lightmaps>();
    handle->layout = bakegi::read_lightmap_layout_file(path);
    *out_lightmaps = handle.release();
  });
}

}  // extern "C"
