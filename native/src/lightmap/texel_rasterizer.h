// Lightmap texels as bake points: one mesh's triangles are rasterized in lightmap UV space,
// conservatively, and every (texel, triangle) overlap becomes one sample on the surface.
//
// Texel (x, y) of a W x H lightmap covers [x, x+1] x [y, y+1] in pixel units (u * W, v * H),
// row 0 at v = 0 as in Blender. Guarantees (tested in test_lightmap_rasterizer.cpp):
//  - a texel is baked (has samples, covered = 1) iff some non-degenerate triangle overlaps
//    it with positive area: every texel whose centre lies inside a triangle is baked, and so
//    is a texel only partly covered at a chart's edge (so bilinear filtering at the edge
//    reads baked light, not the gutter); texels outside all triangles are not baked;
//  - a sample's weight is the fraction of its texel the triangle covers (0, 1], exact
//    (polygon clipping), so the weights of a texel sum to its covered fraction;
//  - a sample lies on its triangle: the texel centre's barycentrics, moved to the closest
//    point of the triangle in UV space when the centre lies outside it (an edge texel), so
//    the sample is never extrapolated off the surface;
//  - triangles with (almost) zero UV area, or zero world area, are skipped and counted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bake_points.h"
#include "util/cancel_flag.h"

namespace bakegi {

// The largest lightmap side: 8192^2 texels take about 2 GB while written (image, mask,
// weights, EXR scanlines).
inline constexpr uint32_t kMaxLightmapSide = 8192;

struct LightmapTriangle {
  glm::vec3 p[3];   // world positions
  glm::vec3 n[3];   // shading normals; zero (or not finite) = use the face normal
  glm::vec2 uv[3];  // lightmap UVs; parts outside [0,1]^2 are clipped away
};

struct TexelSamples {
  uint32_t width = 0, height = 0;
  BakePoints points;                       // one per sample (object ids = the given object id)
  std::vector<glm::vec3> face_normals;     // per sample: its triangle's unit geometric normal
  std::vector<uint32_t> texel;             // per sample: y * width + x
  std::vector<float> weight;               // per sample: covered fraction of its texel
  std::vector<uint8_t> covered;            // per texel: 1 if it has at least one sample
  size_t skipped_degenerate_uv = 0;        // triangles with negligible UV area
  size_t skipped_degenerate_geometry = 0;  // triangles with zero world area

  size_t size() const { return texel.size(); }
  size_t covered_texels() const;
};

// Rasterizes triangles into a width x height lightmap (both >= 1). Throws
// Error(INVALID_ARGUMENT) for a zero size or non-finite input, naming the triangle.
// An upper bound of the samples rasterize_texels makes (without making them), to check a
// memory budget first: a convex shape of area A and perimeter P (in texels) overlaps at
// most A + 2*sqrt(2)*P + 4 unit squares (its Minkowski sum with a texel), and never more
// than the texels of its bounding box.
uint64_t max_texel_samples(const std::vector<LightmapTriangle>& triangles, uint32_t width,
                           uint32_t height);

// `cancel` (optional) is checked at every texel row: Error(CANCELLED) when raised.
TexelSamples rasterize_texels(const std::vector<LightmapTriangle>& triangles, uint32_t width,
                              uint32_t height, uint32_t object_id = 0,
                              const CancelFlag* cancel = nullptr);

// Keeps only the samples where keep[i] is true, and recomputes the coverage mask (a texel
// whose samples were all dropped becomes uncovered, to be filled from its neighbours).
void keep_samples(TexelSamples& samples, const std::vector<bool>& keep);

// Appends `more` (rasterized at the same size, e.g. another object whose UVs lie in its own
// region of a shared atlas) to `into`: samples concatenated in that order, coverage masks
// OR-ed, skipped-triangle counters summed. Throws Error(INVALID_ARGUMENT) if the sizes
// differ. Where both cover a texel (overlapping UVs), its samples are averaged by coverage
// like those of two triangles of one mesh.
void append_samples(TexelSamples& into, TexelSamples&& more);

}  // namespace bakegi
