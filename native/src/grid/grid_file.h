// The .bgivg file: one baked Irradiance Vector Grid, in the framed format of every bakegi
// file (util/framed_file.h: magic "BAKEGI\0V", version, size, payload, FNV-1a checksum).
// Payload, little-endian:
//   f32 bounds_min[3], f32 bounds_max[3], u32 resolution[3]  (vertices along x, y, z)
//   u32 encoding        0 = float: 6 hemispheres x 3x3 f32 per vertex (column per channel)
//                       1 = quantized (§3.3): per hemisphere u8 direction[3] then u32
//                           R9G9B9E5 colour, 7 bytes
//                       2 = factored (§3.3 without quantization): per hemisphere f32
//                           direction[3] then f32 colour[3], 24 bytes
//   u8  valid[vertex count]   1 = gathered, 0 = filled by push-pull (inside geometry)
//   the hemispheres, vertex by vertex (x fastest, then y, then z), +x -x +y -y +z -z
//   version 2 only: the emitted light's hemispheres (irradiance_vector_grid.h), the same way
//   u32 length, UTF-8 JSON: what made the grid (method, rays, seconds), for people
// A grid without emitted light is written as version 1.
// The web client (addon/web) reads the same bytes.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "grid/irradiance_vector_grid.h"

namespace bakegi {

// The values of bakegi_grid_encoding (bakegi.h).
enum class GridEncoding : uint32_t { kFloat = 0, kQuantized = 1, kFactored = 2 };

// Bytes per hemisphere in each encoding.
inline constexpr size_t hemisphere_bytes_of(GridEncoding encoding) {
  return encoding == GridEncoding::kFloat ? 36 : encoding == GridEncoding::kQuantized ? 7 : 24;
}

std::vector<uint8_t> encode_grid_file(const IrradianceVectorGrid& grid, GridEncoding encoding,
                                      const std::string& info_json);

struct GridFile {
  IrradianceVectorGrid grid;
  GridEncoding encoding = GridEncoding::kFloat;  // quantized and factored are expanded
  std::string info_json;
};

// Throws Error(BAD_FILE) naming `name` and what is wrong.
GridFile decode_grid_file(std::span<const uint8_t> bytes, const std::string& name);

// Files larger than this are refused before they are read (a 1024^3 float grid would be
// 232 GB; a 256^3 one is 3.6 GB).
inline constexpr uint64_t kMaxGridFileBytes = uint64_t(4) << 30;

}  // namespace bakegi
