// UV seams of a lightmap: mesh edges whose two triangles read the lightmap in different
// places (a chart boundary), found when a mesh is rasterized and kept with the lightmap so
// that the EXR writer can stitch them (lightmap/seam_stitching.h).
//
// An edge is a seam when exactly two triangles share it (the same two vertex indices, in
// either order) and their lightmap UVs at either end differ by more than kSeamUvEpsilon.
// Edges of one triangle (borders), or of three or more (non-manifold), are not seams; nor
// are edges where the two sides' shading normals differ by more than kSeamMaxNormalAngle at
// either end: there the lighting itself is discontinuous (a folded or hard edge, a wall
// meeting the floor), and pulling both sides to one value would blur a real edge. Triangles
// that the rasterizer skips (zero world or UV area) bake no texels and take part in no seam.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "lightmap/texel_rasterizer.h"
#include "util/cancel_flag.h"

namespace bakegi {

// UV distance (UV units) under which two corners of an edge count as the same place.
inline constexpr float kSeamUvEpsilon = 1e-6f;
// cos(10 degrees): smooth-shaded meshes share one normal per vertex (cos = 1); flat
// shading stitches coplanar or nearly flat faces only.
inline constexpr float kSeamMinNormalCos = 0.98480775f;

// One seam edge: its two sides' UVs at the edge's two vertices, endpoint k of side a and
// endpoint k of side b being the same mesh vertex.
struct LightmapSeam {
  glm::vec2 a[2];
  glm::vec2 b[2];
};

// Seams of one mesh: `indices` holds 3 vertex indices per triangle, `triangles` the same
// triangles as given to rasterize_texels (UVs, positions and normals per corner); the
// lightmap size decides (as in the rasterizer) which triangles have zero UV area. Each seam
// is listed once, in the order of its first triangle. Throws Error(INVALID_ARGUMENT) if
// the counts differ, Error(CANCELLED) when `cancel` is raised.
std::vector<LightmapSeam> find_lightmap_seams(std::span<const uint32_t> indices,
                                              const std::vector<LightmapTriangle>& triangles,
                                              uint32_t width, uint32_t height,
                                              const CancelFlag* cancel = nullptr);

}  // namespace bakegi
