#include "lightmap/lightmap_set.h"

#include <cmath>
#include <limits>
#include <string>

#include "lightmap/lightmap_padding.h"
#include "lightmap/lightmap_seams.h"
#include "lightmap/seam_stitching.h"
#include "lightmap/texel_rasterizer.h"
#include "lightmap/texel_sharing.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "util/error.h"

namespace bakegi {
namespace {

// A sample costs 48 bytes here (position, normal, object id, face normal, texel, weight) and
// 28 more as a bake point of the job.
constexpr uint64_t kBytesPerSample = 48 + 28;

// The mesh's triangles with the caller's lightmap UVs, as the rasterizer takes them.
std::vector<LightmapTriangle> lightmap_triangles(const Mesh& mesh, const float* uvs) {
  const size_t triangle_count = mesh.indices.size() / 3;
  std::vector<LightmapTriangle> triangles(triangle_count);
  for (size_t t = 0; t < triangle_count; ++t) {
    LightmapTriangle& tri = triangles[t];
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

void LightmapSet::set_sample_budget_megabytes(uint64_t megabytes) {
  if (megabytes < 1 || megabytes > (uint64_t(1) << 30)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "memory budget must be in [1, 1073741824] MB, got " + std::to_string(megabytes));
  }
  sample_budget_bytes_ = megabytes << 20;
}

// Refuses, before anything is allocated, a mesh whose samples could take the lightmaps over
// the budget (an upper bound, so a refusal names the density, not a crash).
void LightmapSet::check_sample_budget(const std::vector<LightmapTriangle>& triangles,
                                      uint32_t width, uint32_t height) const {
  const uint64_t bound = layout_.total_points() + max_texel_samples(triangles, width, height);
  if (bound > sample_budget_bytes_ / kBytesPerSample) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                "the lightmaps could need up to " + std::to_string(bound) + " texel samples (" +
                    std::to_string(bound * kBytesPerSample >> 20) + " MiB), more than the " +
                    std::to_string(sample_budget_bytes_ >> 20) +
                    " MiB budget; lower the texel density or the lightmap size");
  }
}

LightmapLayout::Lightmap& LightmapSet::lightmap(uint32_t index) {
  if (index >= layout_.lightmaps.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap " + std::to_string(index) +
                                                   " does not exist (there are " +
                                                   std::to_string(layout_.lightmaps.size()) + ")");
  }
  return layout_.lightmaps[index];
}

const LightmapLayout::Lightmap& LightmapSet::lightmap(uint32_t index) const {
  return const_cast<LightmapSet*>(this)->lightmap(index);
}

uint32_t LightmapSet::add(const Mesh& mesh, const float* uvs, uint32_t width, uint32_t height) {
  if (width < 1 || height < 1 || width > kMaxLightmapSide || height > kMaxLightmapSide) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "lightmap size " + std::to_string(width) + " x " +
                                                   std::to_string(height) + " is not in 1.." +
                                                   std::to_string(kMaxLightmapSide));
  }
  const std::vector<LightmapTriangle> triangles = lightmap_triangles(mesh, uvs);
  check_sample_budget(triangles, width, height);
  LightmapLayout::Lightmap added;
  added.samples = rasterize_texels(triangles, width, height, mesh.object_id, cancel_.get());
  added.seams = find_lightmap_seams(mesh.indices, triangles, width, height, cancel_.get());
  layout_.lightmaps.push_back(std::move(added));
  return uint32_t(layout_.lightmaps.size() - 1);
}

void LightmapSet::add_to(uint32_t index, const Mesh& mesh, const float* uvs) {
  if (layout_.rejected_inside) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "bakegi_lightmaps_reject_inside has already run: samples added now would not "
                "be checked (add every mesh first, then reject)");
  }
  LightmapLayout::Lightmap& target = lightmap(index);
  const std::vector<LightmapTriangle> triangles = lightmap_triangles(mesh, uvs);
  const uint32_t width = target.samples.width, height = target.samples.height;
  check_sample_budget(triangles, width, height);
  TexelSamples samples = rasterize_texels(triangles, width, height, mesh.object_id, cancel_.get());
  const std::vector<LightmapSeam> seams =
      find_lightmap_seams(mesh.indices, triangles, width, height, cancel_.get());
  // Room first, so that nothing after the samples are appended can fail.
  target.seams.reserve(target.seams.size() + seams.size());
  append_samples(target.samples, std::move(samples));
  target.seams.insert(target.seams.end(), seams.begin(), seams.end());
}

uint64_t LightmapSet::reject_inside(const SceneDescription& scene,
                                    const BackfaceRejectionOptions& options) {
  throw_if_cancelled(cancel_.get(), "rejecting texels inside geometry");
  const Scene built = build_scene(scene);
  throw_if_cancelled(cancel_.get(), "rejecting texels inside geometry");
  const RayTracer tracer(built);
  uint64_t rejected = 0;
  for (LightmapLayout::Lightmap& each : layout_.lightmaps) {
    TexelSamples& samples = each.samples;
    const std::vector<uint8_t> flags =
        flag_samples_inside_geometry(built, tracer, samples.points.positions, samples.face_normals,
                                     samples.points.normals, options, cancel_.get());
    // Samples are dropped from here on: refuse later additions even if this call then
    // fails (a call refused for its options above has changed nothing).
    layout_.rejected_inside = true;
    std::vector<bool> keep(flags.size());
    uint64_t dropped = 0;
    for (size_t i = 0; i < flags.size(); ++i) {
      keep[i] = !flags[i];
      dropped += flags[i];
    }
    keep_samples(samples, keep);
    each.rejected_samples += dropped;
    rejected += dropped;
  }
  layout_.rejected_inside = true;
  return rejected;
}

BakePoints LightmapSet::points() const {
  const uint64_t total = layout_.total_points();
  if (total == 0) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "the lightmaps have no texel samples (no lightmap added, or no triangle "
                "covers a texel)");
  }
  // Share candidates are 32-bit indices.
  if (total > std::numeric_limits<uint32_t>::max()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "the lightmaps have " + std::to_string(total) + " texel samples, more than " +
                    std::to_string(std::numeric_limits<uint32_t>::max()));
  }
  BakePoints points;
  points.positions.reserve(total);
  points.normals.reserve(total);
  points.object_ids.reserve(total);
  points.share_candidates.reserve(total);
  for (const LightmapLayout::Lightmap& l : layout_.lightmaps) {
    const BakePoints& p = l.samples.points;
    // Samples of one texel on one surface are baked once (lightmap/texel_sharing.h).
    const std::vector<uint32_t> candidates =
        texel_share_candidates(l.samples, points.positions.size());
    points.positions.insert(points.positions.end(), p.positions.begin(), p.positions.end());
    points.normals.insert(points.normals.end(), p.normals.begin(), p.normals.end());
    points.object_ids.insert(points.object_ids.end(), p.object_ids.begin(), p.object_ids.end());
    points.share_candidates.insert(points.share_candidates.end(), candidates.begin(),
                                   candidates.end());
  }
  return points;
}

RgbImage LightmapSet::resolve(uint32_t index, const float* rgb, uint64_t count,
                              uint32_t padding) const {
  const LightmapLayout::Lightmap& l = lightmap(index);
  const uint64_t total = layout_.total_points();
  if (count != total) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "count " + std::to_string(count) + " differs from the lightmaps' " +
                    std::to_string(total) + " points (pass the whole bake result)");
  }
  if (padding > kMaxPadding) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "padding " + std::to_string(padding) + " is over " + std::to_string(kMaxPadding));
  }
  // Esc during the write-back: the add-on writes the EXR on a worker thread and cancels here
  // and in the EXR writer; resolving and writing a 2048² map takes ~0.25 s in all, a cancel
  // stops it within ~50 ms (LightmapApi.CancelStopsTheWriteBack).
  const char* work = "writing the lightmap";
  throw_if_cancelled(cancel_.get(), work);
  const uint64_t first = layout_.first_point(index);
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
  RgbImage image = resolve_texels(l.samples, values.data(), filled);
  throw_if_cancelled(cancel_.get(), work);
  dilate_texels(image, filled, padding);
  throw_if_cancelled(cancel_.get(), work);
  stitch_seams(image, l.samples.covered, filled, l.seams);
  throw_if_cancelled(cancel_.get(), work);
  return image;
}

}  // namespace bakegi
