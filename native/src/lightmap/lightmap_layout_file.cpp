#include "lightmap/lightmap_layout_file.h"

#include <cmath>
#include <cstring>

#include "util/byte_stream.h"
#include "util/error.h"
#include "util/file_bytes.h"
#include "util/framed_file.h"

namespace bakegi {

namespace {

constexpr char kMagic[8] = {'B', 'A', 'K', 'E', 'G', 'I', '\0', 'L'};
constexpr uint32_t kLightmapSection = section_tag("LMAP");
constexpr uint32_t kRejectedInside = 1;
// Bytes per sample: position, normal, object id, face normal, texel, weight.
constexpr uint64_t kSampleBytes = 12 + 12 + 4 + 12 + 4 + 4;
// Bytes per seam: four UVs.
constexpr uint64_t kSeamBytes = 4 * 8;
// Version 1 had no seams; its files read as lightmaps without any.
constexpr uint32_t kFirstVersionWithSeams = 2;
// The fixed part of a lightmap section: width, height and four u64 counters.
constexpr uint64_t kLightmapHeaderBytes = 4 + 4 + 4 * 8;
// A layout the writer can hold in memory is far smaller; this only keeps a wrong path (a
// disk image, say) from being read whole.
constexpr uint64_t kMaxFileBytes = uint64_t(16) << 30;

void write_lightmap(ByteWriter& w, const LightmapLayout::Lightmap& lightmap) {
  const TexelSamples& s = lightmap.samples;
  const size_t at = w.begin_section(kLightmapSection);
  w.u32(s.width);
  w.u32(s.height);
  w.u64(s.size());
  w.u64(lightmap.rejected_samples);
  w.u64(s.skipped_degenerate_uv);
  w.u64(s.skipped_degenerate_geometry);
  for (const glm::vec3& p : s.points.positions) w.vec3(p);
  for (const glm::vec3& n : s.points.normals) w.vec3(n);
  for (uint32_t id : s.points.object_ids) w.u32(id);
  for (const glm::vec3& n : s.face_normals) w.vec3(n);
  for (uint32_t t : s.texel) w.u32(t);
  for (float weight : s.weight) w.f32(weight);
  // Coverage as a bit mask, texel t in bit t % 32 of word t / 32.
  std::vector<uint32_t> words((s.covered.size() + 31) / 32, 0);
  for (size_t t = 0; t < s.covered.size(); ++t) {
    if (s.covered[t]) words[t / 32] |= uint32_t(1) << (t % 32);
  }
  for (uint32_t word : words) w.u32(word);
  w.u64(lightmap.seams.size());
  for (const LightmapSeam& seam : lightmap.seams) {
    for (const glm::vec2& uv : {seam.a[0], seam.a[1], seam.b[0], seam.b[1]}) w.vec2(uv);
  }
  w.end_section(at);
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Reads one lightmap section's contents and checks them against what the rasterizer makes,
// so that the C API never works on samples it could not have produced.
LightmapLayout::Lightmap read_lightmap(ByteReader& r, size_t index, uint32_t version) {
  const std::string name = "lightmap " + std::to_string(index);
  auto fail = [&](const std::string& what) { r.fail(name + ": " + what); };
  LightmapLayout::Lightmap lightmap;
  TexelSamples& s = lightmap.samples;
  s.width = r.u32();
  s.height = r.u32();
  if (s.width < 1 || s.height < 1 || s.width > kMaxLightmapSide || s.height > kMaxLightmapSide) {
    fail("size " + std::to_string(s.width) + " x " + std::to_string(s.height) + " is not in 1.." +
         std::to_string(kMaxLightmapSide));
  }
  const uint64_t count = r.u64();
  lightmap.rejected_samples = r.u64();
  s.skipped_degenerate_uv = r.u64();
  s.skipped_degenerate_geometry = r.u64();
  const uint64_t texels = uint64_t(s.width) * s.height;
  // Checked as a whole before any array is allocated (each is checked again as read).
  r.need(count, kSampleBytes, "lightmap samples");
  r.array(s.points.positions, count, 12, "sample positions", [&] { return r.vec3(); });
  r.array(s.points.normals, count, 12, "sample normals", [&] { return r.vec3(); });
  r.array(s.points.object_ids, count, 4, "sample object ids", [&] { return r.u32(); });
  r.array(s.face_normals, count, 12, "sample face normals", [&] { return r.vec3(); });
  r.array(s.texel, count, 4, "sample texels", [&] { return r.u32(); });
  r.array(s.weight, count, 4, "sample weights", [&] { return r.f32(); });
  std::vector<uint32_t> words;
  r.array(words, (texels + 31) / 32, 4, "texel coverage", [&] { return r.u32(); });
  s.covered.resize(texels);
  for (uint64_t t = 0; t < texels; ++t) s.covered[t] = uint8_t(words[t / 32] >> (t % 32) & 1);
  if (texels % 32 != 0 && words.back() >> (texels % 32) != 0) fail("coverage bits past the map");
  if (version >= kFirstVersionWithSeams) {
    const uint64_t seams = r.u64();
    r.array(lightmap.seams, seams, kSeamBytes, "seams", [&] {
      LightmapSeam seam;
      for (glm::vec2* uv : {&seam.a[0], &seam.a[1], &seam.b[0], &seam.b[1]}) *uv = r.vec2();
      return seam;
    });
    for (size_t i = 0; i < lightmap.seams.size(); ++i) {
      const LightmapSeam& seam = lightmap.seams[i];
      for (const glm::vec2& uv : {seam.a[0], seam.a[1], seam.b[0], seam.b[1]}) {
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
          fail("seam " + std::to_string(i) + ": a UV is not finite");
        }
      }
    }
  }

  // The rasterizer's invariants: finite positions, unit normals, texels inside the map,
  // weights in (0, 1], and a texel is covered iff it has samples.
  std::vector<uint8_t> has_samples(texels, 0);
  for (uint64_t i = 0; i < count; ++i) {
    const auto sample = [i] { return "sample " + std::to_string(i); };
    if (!finite(s.points.positions[i])) fail(sample() + ": position is not finite");
    const float length = glm::length(s.points.normals[i]);
    const float face_length = glm::length(s.face_normals[i]);
    if (!(std::abs(length - 1.0f) < 1e-3f) || !(std::abs(face_length - 1.0f) < 1e-3f)) {
      fail(sample() + ": normal or face normal is not unit length");
    }
    if (s.texel[i] >= texels) {
      fail(sample() + ": texel " + std::to_string(s.texel[i]) + " is outside the " +
           std::to_string(s.width) + " x " + std::to_string(s.height) + " map");
    }
    if (!(s.weight[i] > 0.0f && s.weight[i] <= 1.0f)) {
      fail(sample() + ": weight " + std::to_string(s.weight[i]) + " is not in (0, 1]");
    }
    has_samples[s.texel[i]] = 1;
  }
  if (has_samples != s.covered) fail("the coverage does not match the samples' texels");
  return lightmap;
}

}  // namespace

std::vector<uint8_t> encode_lightmap_layout(const LightmapLayout& layout) {
  ByteWriter w = begin_framed_file(kMagic, kLightmapLayoutFileVersion);
  w.u32(layout.rejected_inside ? kRejectedInside : 0);
  w.u32(uint32_t(layout.lightmaps.size()));
  for (const LightmapLayout::Lightmap& lightmap : layout.lightmaps) write_lightmap(w, lightmap);
  return finish_framed_file(w);
}

LightmapLayout decode_lightmap_layout(std::span<const uint8_t> bytes, const std::string& name) {
  auto fail = [&](const std::string& what) -> void {
    throw Error(BAKEGI_ERROR_BAD_FILE, name + ": " + what);
  };
  const FramedPayload framed =
      open_framed_file(bytes, kMagic, 1, kLightmapLayoutFileVersion, "lightmap layout file", name);
  const uint32_t version = framed.version;
  LightmapLayout layout;
  ByteReader r(framed.payload, name);
  const uint32_t flags = r.u32();
  if (flags & ~kRejectedInside) fail("unknown flags " + std::to_string(flags));
  layout.rejected_inside = (flags & kRejectedInside) != 0;
  const uint32_t count = r.u32();
  // Each lightmap takes at least its section header and fixed fields.
  r.need(count, 16 + kLightmapHeaderBytes, "lightmaps");
  layout.lightmaps.reserve(count);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t section = r.u32();
    r.u32();
    const uint64_t size = r.u64();
    if (section != kLightmapSection) {
      fail("lightmap " + std::to_string(i) + ": unexpected section at byte " +
           std::to_string(r.position()));
    }
    r.need(size, 1, "lightmap section");
    const size_t end = r.position() + size;
    layout.lightmaps.push_back(read_lightmap(r, i, version));
    if (r.position() != end) {
      fail("lightmap " + std::to_string(i) + ": section size does not match its contents");
    }
  }
  if (r.left() != 0) fail("unexpected bytes after the last lightmap");
  return layout;
}

void write_lightmap_layout_file(const std::string& path, const LightmapLayout& layout) {
  write_file_atomically(utf8_path(path), encode_lightmap_layout(layout));
}

LightmapLayout read_lightmap_layout_file(const std::string& path) {
  return decode_lightmap_layout(read_file_bytes(utf8_path(path), kMaxFileBytes), path);
}

}  // namespace bakegi
