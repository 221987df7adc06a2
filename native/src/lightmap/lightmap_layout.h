// What a set of lightmaps is between rasterization and the EXR writer: each lightmap's texel
// samples, in the order their bake points are concatenated for the one bake of them all,
// and its UV seams (stitched when the EXR is written).
// The C API's bakegi_lightmaps handle holds one; the .bgl file (lightmap_layout_file.h)
// stores one so that the CLI writes the EXRs of a scene file baked without Blender.
#pragma once

#include <cstdint>
#include <vector>

#include "lightmap/lightmap_seams.h"
#include "lightmap/texel_rasterizer.h"

namespace bakegi {

struct LightmapLayout {
  struct Lightmap {
    TexelSamples samples;
    uint64_t rejected_samples = 0;  // dropped as inside or under geometry
    // Of every mesh rasterized into it (in atlas UVs for bakegi_lightmaps_add_to).
    std::vector<LightmapSeam> seams;
  };
  std::vector<Lightmap> lightmaps;
  // Set once inside-geometry rejection has run: samples added after it would be baked
  // without it, so adding more is refused.
  bool rejected_inside = false;

  uint64_t total_points() const {
    uint64_t total = 0;
    for (const Lightmap& l : lightmaps) total += l.samples.size();
    return total;
  }
  // Index of lightmap `index`'s first bake point.
  uint64_t first_point(size_t index) const {
    uint64_t first = 0;
    for (size_t i = 0; i < index && i < lightmaps.size(); ++i) first += lightmaps[i].samples.size();
    return first;
  }
};

}  // namespace bakegi
