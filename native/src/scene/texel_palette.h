// A texture's texels as 8-bit indices into a palette of at most 256 floats, made where the
// texture holds no more distinct channel values than that (every 8-bit image: the add-on
// linearises its 256 levels into floats). Exact: a lookup reads the very floats the texels
// hold, from 3 bytes a texel instead of 12. The path tracer's albedo lookups wait on the first
// load of a texel (Sponza: a fifth of its path tracing time, docs/benchmarks.md section 0n),
// so fewer bytes means more of the texels a bake touches stay in the caches.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

struct TexelPalette {
  std::array<float, 256> values{};
  std::vector<uint8_t> indices;  // 3 a texel (R, G, B), in the order of the texels

  glm::vec3 texel(size_t i) const {
    const uint8_t* c = indices.data() + 3 * i;
    return {values[c[0]], values[c[1]], values[c[2]]};
  }
  size_t bytes() const { return sizeof(values) + indices.size(); }
};

// The palette of `texels`, or null where they hold more than 256 distinct channel values
// (compared bit for bit, so that every lookup returns exactly the stored float).
std::shared_ptr<const TexelPalette> make_texel_palette(const std::vector<glm::vec3>& texels);

}  // namespace bakegi
