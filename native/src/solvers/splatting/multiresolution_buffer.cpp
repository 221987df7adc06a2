#include "solvers/splatting/multiresolution_buffer.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace bakegi {

MultiresolutionBuffer::MultiresolutionBuffer(uint32_t width, uint32_t height, uint32_t levels)
    : width_(width), height_(height) {
  for (uint32_t k = 0; k < levels; ++k) {
    Level l;
    l.width = std::max(1u, (width + (1u << k) - 1) >> k);
    l.height = std::max(1u, (height + (1u << k) - 1) >> k);
    l.light.assign(size_t(l.width) * l.height, glm::vec3(0.0f));
    l.filled.assign(size_t(l.width) * l.height, 0);
    levels_.push_back(std::move(l));
  }
}

void MultiresolutionBuffer::add(const Subsplat& s, const glm::vec3& value) {
  Level& l = levels_[s.level];
  const size_t i = size_t(s.y) * l.width + s.x;
  l.light[i] += value;
  l.filled[i] = 1;
}

void MultiresolutionBuffer::add(const MultiresolutionBuffer& other) {
  for (size_t k = 0; k < levels_.size(); ++k) {
    for (size_t i = 0; i < levels_[k].light.size(); ++i) {
      levels_[k].light[i] += other.levels_[k].light[i];
      levels_[k].filled[i] |= other.levels_[k].filled[i];
    }
  }
}

std::vector<glm::vec3> MultiresolutionBuffer::upsample(Upsampling mode) {
  switch (mode) {
    case Upsampling::kNearest:
      return upsample_nearest();
    case Upsampling::kBilinear:
      return upsample_bilinear();
    default:
      return upsample_interpolated();
  }
}

std::vector<glm::vec3> MultiresolutionBuffer::upsample_interpolated() {
  // Each level's own light becomes, in place, its light plus what the coarser levels hand
  // down: the data of that level.
  for (int k = int(levels_.size()) - 1; k > 0; --k) {
    const Level& l = levels_[size_t(k)];
    Level& fine = levels_[size_t(k) - 1];
    // Each child of a texel with data is interpolated bilinearly from the texel and the
    // neighbours on its side (weights 9, 3, 3, 1 / 16), among those that hold data.
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, fine.height, 16), [&](const auto& rows) {
      for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
        for (uint32_t x = 0; x < fine.width; ++x) {
          const uint32_t px = x / 2, py = y / 2;
          const size_t parent = size_t(py) * l.width + px;
          if (!l.filled[parent]) continue;
          const int sx = (x & 1) ? 1 : -1, sy = (y & 1) ? 1 : -1;
          glm::vec3 sum(0.0f);
          float total = 0.0f;
          for (int j = 0; j <= 1; ++j) {
            for (int i = 0; i <= 1; ++i) {
              const int nx = int(px) + i * sx, ny = int(py) + j * sy;
              if (nx < 0 || ny < 0 || nx >= int(l.width) || ny >= int(l.height)) continue;
              const size_t n = size_t(ny) * l.width + size_t(nx);
              if (!l.filled[n]) continue;
              const float w = (i ? 0.25f : 0.75f) * (j ? 0.25f : 0.75f);
              sum += w * l.light[n];
              total += w;
            }
          }
          const size_t t = size_t(y) * fine.width + x;
          fine.light[t] += sum / total;
          fine.filled[t] = 1;
        }
      }
    });
  }
  return std::move(levels_[0].light);
}

template <typename Sample>
std::vector<glm::vec3> MultiresolutionBuffer::sum_levels(Sample&& sample) const {
  std::vector<glm::vec3> out(size_t(width_) * height_, glm::vec3(0.0f));
  for (uint32_t y = 0; y < height_; ++y) {
    for (uint32_t x = 0; x < width_; ++x) {
      glm::vec3 sum(0.0f);
      for (uint32_t k = 0; k < levels_.size(); ++k) sum += sample(levels_[k], k, x, y);
      out[size_t(y) * width_ + x] = sum;
    }
  }
  return out;
}

std::vector<glm::vec3> MultiresolutionBuffer::upsample_nearest() const {
  return sum_levels([](const Level& l, uint32_t k, uint32_t x, uint32_t y) {
    return l.light[size_t(y >> k) * l.width + (x >> k)];
  });
}

std::vector<glm::vec3> MultiresolutionBuffer::upsample_bilinear() const {
  return sum_levels([](const Level& l, uint32_t k, uint32_t x, uint32_t y) {
    // The pixel centre in this level's texel coordinates (texel centres at +0.5).
    const float scale = 1.0f / float(1u << k);
    const float fx = std::clamp((float(x) + 0.5f) * scale - 0.5f, 0.0f, float(l.width - 1));
    const float fy = std::clamp((float(y) + 0.5f) * scale - 0.5f, 0.0f, float(l.height - 1));
    const uint32_t x0 = uint32_t(fx), y0 = uint32_t(fy);
    const uint32_t x1 = std::min(x0 + 1, l.width - 1), y1 = std::min(y0 + 1, l.height - 1);
    const float ax = fx - float(x0), ay = fy - float(y0);
    const auto at = [&](uint32_t u, uint32_t v) { return l.light[size_t(v) * l.width + u]; };
    return (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) +
           (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
  });
}

void render_subsplats(const SubsplatSet& set, const MinMaxMipmap& mipmap,
                      const PixelLight& pixel_light, MultiresolutionBuffer& buffer) {
  std::vector<glm::vec3> light(set.subsplats.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, set.subsplats.size(), 64), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Subsplat& s = set.subsplats[i];
      const MipLevel& l = mipmap.level(s.level);
      const uint32_t pixel = l.representative[l.index(s.x, s.y)];
      light[i] = pixel_light(pixel);
    }
  });
  for (size_t i = 0; i < set.subsplats.size(); ++i) buffer.add(set.subsplats[i], light[i]);
}

}  // namespace bakegi
