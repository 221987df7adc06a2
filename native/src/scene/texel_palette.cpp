#include "scene/texel_palette.h"

#include <cstring>

namespace bakegi {

namespace {

// Open addressing over the floats' bit patterns: 512 slots for at most 256 values keeps every
// probe short.
class ValueIndex {
 public:
  ValueIndex() {
    for (int16_t& i : index_) i = -1;
  }

  // The value's palette index, added where new; -1 once the palette is full.
  int find_or_add(float value, TexelPalette& palette) {
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    for (uint32_t slot = (bits * 2654435761u) >> 23;; slot = (slot + 1) & (kSlots - 1)) {
      if (index_[slot] < 0) {
        if (count_ == 256) return -1;
        keys_[slot] = bits;
        index_[slot] = int16_t(count_);
        palette.values[count_] = value;
        return count_++;
      }
      if (keys_[slot] == bits) return index_[slot];
    }
  }

 private:
  static constexpr uint32_t kSlots = 512;
  uint32_t keys_[kSlots]{};
  int16_t index_[kSlots];
  int count_ = 0;
};

}  // namespace

std::shared_ptr<const TexelPalette> make_texel_palette(const std::vector<glm::vec3>& texels) {
  auto palette = std::make_shared<TexelPalette>();
  palette->indices.resize(3 * texels.size());
  ValueIndex index;
  uint8_t* out = palette->indices.data();
  for (const glm::vec3& texel : texels) {
    for (int c = 0; c < 3; ++c) {
      const int i = index.find_or_add(texel[c], *palette);
      if (i < 0) return nullptr;
      *out++ = uint8_t(i);
    }
  }
  return palette;
}

}  // namespace bakegi
