#include "grid/grid_file.h"

#include <cmath>

#include "grid/grid_quantization.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/framed_file.h"

namespace bakegi {

namespace {

constexpr char kMagic[8] = {'B', 'A', 'K', 'E', 'G', 'I', '\0', 'V'};
// Version 2 adds the emitted light; a grid without it is written as version 1, which
// readers of before (and the web page) read.
constexpr uint32_t kGridFileVersion = 2;

void write_hemispheres(ByteWriter& w, const std::vector<glm::mat3>& vectors,
                       GridEncoding encoding) {
  for (size_t i = 0; i < vectors.size(); ++i) {
    const glm::mat3& m = vectors[i];
    const int h = int(i % kGridHemispheres);
    if (encoding == GridEncoding::kFloat) {
      for (int c = 0; c < 3; ++c) w.vec3(m[c]);
    } else if (encoding == GridEncoding::kFactored) {
      const FactoredHemisphere f = factor_hemisphere(m, h);
      w.vec3(f.direction);
      w.vec3(f.color);
    } else {
      const QuantizedHemisphere q = quantize_hemisphere(m, h);
      w.u8(q.direction.x);
      w.u8(q.direction.y);
      w.u8(q.direction.z);
      w.u32(q.color);
    }
  }
}

void read_hemispheres(ByteReader& r, std::vector<glm::mat3>& vectors, GridEncoding encoding) {
  for (size_t i = 0; i < vectors.size(); ++i) {
    glm::mat3& m = vectors[i];
    const std::string where = "vertex " + std::to_string(i / kGridHemispheres);
    if (encoding == GridEncoding::kFloat) {
      for (int c = 0; c < 3; ++c) m[c] = r.vec3();
      for (int c = 0; c < 3; ++c) {
        for (int e = 0; e < 3; ++e) {
          if (!std::isfinite(m[c][e])) r.fail("corrupt: a non-finite value at " + where);
        }
      }
    } else if (encoding == GridEncoding::kFactored) {
      const glm::vec3 direction = r.vec3(), color = r.vec3();
      for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(direction[a]) || !std::isfinite(color[a])) {
          r.fail("corrupt: a non-finite value at " + where);
        }
      }
      m = expand_hemisphere(direction, color);
    } else {
      QuantizedHemisphere q;
      q.direction.x = r.u8();
      q.direction.y = r.u8();
      q.direction.z = r.u8();
      q.color = r.u32();
      m = dequantize_hemisphere(q);
    }
  }
}

}  // namespace

std::vector<uint8_t> encode_grid_file(const IrradianceVectorGrid& grid, GridEncoding encoding,
                                      const std::string& info_json) {
  ByteWriter w = begin_framed_file(kMagic, grid.has_emitted() ? kGridFileVersion : 1);
  const GridLayout& layout = grid.layout;
  w.vec3(layout.bounds_min);
  w.vec3(layout.bounds_max);
  for (uint32_t r : layout.resolution) w.u32(r);
  w.u32(uint32_t(encoding));
  const size_t count = grid.vertex_count();
  const size_t components = grid.has_emitted() ? 2 : 1;
  w.bytes.reserve(w.bytes.size() +
                  count * (1 + components * kGridHemispheres * hemisphere_bytes_of(encoding)));
  for (size_t v = 0; v < count; ++v) w.u8(grid.valid[v] ? 1 : 0);
  write_hemispheres(w, grid.vectors, encoding);
  if (grid.has_emitted()) write_hemispheres(w, grid.emitted, encoding);
  w.string(info_json);
  return finish_framed_file(w);
}

GridFile decode_grid_file(std::span<const uint8_t> bytes, const std::string& name) {
  const FramedPayload framed =
      open_framed_file(bytes, kMagic, 1, kGridFileVersion, "irradiance vector grid", name);
  ByteReader r(framed.payload, name);
  GridFile file;
  const glm::vec3 lo = r.vec3(), hi = r.vec3();
  std::array<uint32_t, 3> resolution{};
  for (uint32_t& n : resolution) n = r.u32();
  GridLayout layout;
  try {
    layout = make_grid_layout(lo, hi, resolution);
  } catch (const Error& e) {
    r.fail(std::string("corrupt: ") + e.what());
  }
  // make_grid_layout may widen a flat axis; a file stores the widened bounds already.
  const uint32_t encoding = r.u32();
  if (encoding > uint32_t(GridEncoding::kFactored)) {
    r.fail("unknown encoding " + std::to_string(encoding));
  }
  file.encoding = GridEncoding(encoding);
  const size_t count = layout.vertex_count();
  const size_t hemisphere_bytes = hemisphere_bytes_of(file.encoding);
  // Check the sizes before allocating the grid.
  r.need(count, 1 + kGridHemispheres * hemisphere_bytes, "grid vertices");
  file.grid = IrradianceVectorGrid(layout);
  for (size_t v = 0; v < count; ++v) {
    const uint8_t flag = r.u8();
    if (flag > 1)
      r.fail("corrupt: vertex " + std::to_string(v) + " has validity " + std::to_string(flag));
    file.grid.valid[v] = flag;
  }
  read_hemispheres(r, file.grid.vectors, file.encoding);
  if (framed.version >= 2) {
    r.need(count, kGridHemispheres * hemisphere_bytes, "the emitted light");
    file.grid.emitted.assign(file.grid.vectors.size(), glm::mat3(0.0f));
    read_hemispheres(r, file.grid.emitted, file.encoding);
  }
  file.info_json = r.string();
  if (r.left() != 0) r.fail("unexpected bytes after the grid");
  return file;
}

}  // namespace bakegi
