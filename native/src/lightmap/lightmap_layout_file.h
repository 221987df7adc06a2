// The .bgl lightmap layout file: a LightmapLayout (every lightmap's size, samples, coverage, seams
// and counters), so that the CLI can write the EXRs of a .bgs scene file whose bake points
// came from the same layout (bakegi.export_scene_file(target='LIGHTMAP') writes both).
//
// Layout, all little-endian, the conventions of the .bgs file (scene/scene_file.h):
//   header   "BAKEGI\0L", u32 format version, u32 reserved (0), u64 payload bytes
//   payload  u32 flags (1 = inside-geometry rejection has run), u32 lightmap count, then one
//            section per lightmap: u32 tag "LMAP", u32 reserved (0), u64 bytes, then
//              u32 width, u32 height, u64 samples, u64 rejected samples,
//              u64 triangles skipped for zero UV area, u64 for zero world area,
//              per sample (each array in turn): position vec3, shading normal vec3,
//              object id u32, face normal vec3, texel u32 (y * width + x), weight f32,
//              coverage: width * height bits in u32 words, bit t % 32 of word t / 32
//              set where texel t has samples,
//              (version 2 on) u64 seams, per seam 4 UVs as vec2 f32: side A's at the
//              edge's two vertices, then side B's at the same two (LightmapSeam)
//   trailer  u64 FNV-1a 64 hash of header and payload
// Reading checks the hash, and every count against the bytes left before it allocates;
// then that the contents are what the rasterizer makes (sizes 1..kMaxLightmapSide, unit
// normals, texels inside the map, weights in (0, 1], coverage = the texels with samples,
// finite seam UVs). Anything else is Error(BAD_FILE) naming what is wrong. Version 1 files
// (before seams) are still read, as lightmaps without seams (written unstitched).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "lightmap/lightmap_layout.h"

namespace bakegi {

// Writes this version; reads 1 (no seams) and 2.
inline constexpr uint32_t kLightmapLayoutFileVersion = 2;

std::vector<uint8_t> encode_lightmap_layout(const LightmapLayout& layout);
// Throws Error(BAD_FILE) naming what is wrong; `name` prefixes the messages.
LightmapLayout decode_lightmap_layout(std::span<const uint8_t> bytes, const std::string& name);

// Path in UTF-8. Writing goes through a temporary file and a rename (an existing file is
// replaced only by a complete one). Throw Error(IO) when the file cannot be written or
// read, Error(BAD_FILE) as above (also for a file over 16 GiB, checked before reading it).
void write_lightmap_layout_file(const std::string& path, const LightmapLayout& layout);
LightmapLayout read_lightmap_layout_file(const std::string& path);

}  // namespace bakegi
