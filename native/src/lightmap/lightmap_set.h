// The lightmaps of one bake, from meshes to images: each mesh's triangles are rasterized
// into texel samples (refused before allocation beyond the sample budget), samples inside
// geometry are dropped, all samples become the bake's points, and a baked result is
// resolved into each lightmap's image (texel means, padding, seam stitching). The C API's
// bakegi_lightmaps handle is one of these; the EXR writer and bakegi_lightmaps_resolve (the
// add-on's image fill) are consumers of resolve().
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "lightmap/backface_rejection.h"
#include "lightmap/exr_writer.h"
#include "lightmap/lightmap_layout.h"
#include "scene/bake_points.h"
#include "scene/scene.h"
#include "util/cancel_flag.h"

namespace bakegi {

class LightmapSet {
 public:
  // The core's default memory budget (memory_budget_mb 4096) until set_sample_budget.
  static constexpr uint64_t kDefaultSampleBudgetBytes = uint64_t(4096) << 20;
  static constexpr uint32_t kMaxPadding = 1024;

  LightmapSet() = default;
  explicit LightmapSet(LightmapLayout layout) : layout_(std::move(layout)) {}

  // What the texel samples of all lightmaps may take; megabytes in [1, 2^30].
  void set_sample_budget_megabytes(uint64_t megabytes);

  // A new width x height lightmap for `mesh`; uvs: 2 floats per triangle corner (the
  // mesh's lightmap UVs). Returns its index. Nothing changes when it throws.
  uint32_t add(const Mesh& mesh, const float* uvs, uint32_t width, uint32_t height);
  // Rasterizes `mesh` into lightmap `lightmap` too (an atlas; uvs already in its region).
  void add_to(uint32_t lightmap, const Mesh& mesh, const float* uvs);
  // Drops the samples inside or under geometry of `scene`; returns how many. Later
  // add/add_to are refused (their samples would not be checked).
  uint64_t reject_inside(const SceneDescription& scene, const BackfaceRejectionOptions& options);

  // All lightmaps' samples, concatenated in the order added: the bake's points.
  BakePoints points() const;

  // Raised from any thread: a running or later add, add_to or reject_inside stops with
  // Error(CANCELLED) within a texel row or 64 samples, and the set keeps no partial samples
  // of it. (The add-on cancels a lightmap bake's texel work on Esc.) Sticky.
  void cancel() { cancel_->store(true, std::memory_order_relaxed); }
  // The flag cancel() raises, for work on this set's results (the EXR writer).
  const CancelFlag* cancel_flag() const { return cancel_.get(); }

  // Lightmap `lightmap` as an image (bottom-up, like Blender's): rgb holds 3 floats for
  // each of the count points of points() (the whole bake result); texels get the mean of
  // their samples, `padding` rounds of dilation fill the gutters, and UV seams are
  // stitched. Throws INVALID_ARGUMENT for a wrong count, a value that is not finite or a
  // padding over kMaxPadding, CANCELLED between its steps once cancel() was called.
  RgbImage resolve(uint32_t lightmap, const float* rgb, uint64_t count, uint32_t padding) const;

  const LightmapLayout& layout() const { return layout_; }
  const LightmapLayout::Lightmap& lightmap(uint32_t index) const;

 private:
  LightmapLayout::Lightmap& lightmap(uint32_t index);
  void check_sample_budget(const std::vector<LightmapTriangle>& triangles, uint32_t width,
                           uint32_t height) const;

  LightmapLayout layout_;
  uint64_t sample_budget_bytes_ = kDefaultSampleBudgetBytes;
  // Held apart so that the set stays movable (a layout read from a file is moved in).
  std::shared_ptr<CancelFlag> cancel_ = std::make_shared<CancelFlag>(false);
};

}  // namespace bakegi
