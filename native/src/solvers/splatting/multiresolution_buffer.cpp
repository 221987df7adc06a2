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
  l.light[i] = l.at(i) + value;
  l.filled[i] = 1;
}

void MultiresolutionBuffer::add(const MultiresolutionBuffer& other) {
  for (size_t k = 0; k < levels_.size(); ++k) {
    const Level& o = other.levels_[k];
    Level& l = levels_[k];
    for (size_t i = 0; i < l.light.size(); ++i) {
      if (!o.filled[i]) continue;
      l.light[i] = l.at(i) + o.light[i];
      l.filled[i] = 1;
    }
  }
}

void MultiresolutionBuffer::clear() {
  for (Level& l : levels_) std::fill(l.filled.begin(), l.filled.end(), uint8_t(0));
}

std::vector<glm::vec3> MultiresolutionBuffer::upsample(Upsampling mode) {
  std::vector<glm::vec3> image;
  upsample(mode, image);
  return image;
}

void MultiresolutionBuffer::upsample(Upsampling mode, std::vector<glm::vec3>& image) {
  image.resize(size_t(width_) * height_);
  switch (mode) {
    case Upsampling::kNearest:
      return upsample_nearest(image);
    case Upsampling::kBilinear:
      return upsample_bilinear(image);
    default:
      return upsample_interpolated(image);
  }
}

void MultiresolutionBuffer::upsample_interpolated(std::vector<glm::vec3>& image) {
  // Each level's own light becomes, in place, its light plus what the coarser levels hand
  // down: the data of that level.
  for (int k = int(levels_.size()) - 1; k > 0; --k) {
    const Level& l = levels_[size_t(k)];
    Level& fine = levels_[size_t(k) - 1];
    // Each child of a texel with data is interpolated bilinearly from the texel and the
    // neighbours on its side (weights 9, 3, 3, 1 / 16). A neighbour without data (refined
    // further, or beyond the image) is extrapolated linearly from the texel and the one
    // opposite; holding the light constant instead would flatten every gradient that runs
    // into a refined region.
    const auto data = [&](int nx, int ny, glm::vec3& v) {
      if (nx < 0 || ny < 0 || nx >= int(l.width) || ny >= int(l.height)) return false;
      const size_t n = size_t(ny) * l.width + size_t(nx);
      if (!l.filled[n]) return false;
      v = l.light[n];
      return true;
    };
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, fine.height, 16), [&](const auto& rows) {
      for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
        for (uint32_t x = 0; x < fine.width; ++x) {
          const int px = int(x / 2), py = int(y / 2);
          glm::vec3 p;
          if (!data(px, py, p)) continue;
          const int sx = (x & 1) ? 1 : -1, sy = (y & 1) ? 1 : -1;
          glm::vec3 a, b, c, o;
          bool has_a = data(px + sx, py, a), has_b = data(px, py + sy, b);
          if (!has_a && data(px - sx, py, o)) a = 2.0f * p - o, has_a = true;
          if (!has_b && data(px, py - sy, o)) b = 2.0f * p - o, has_b = true;
          bool has_c = data(px + sx, py + sy, c);
          if (!has_c && has_a && has_b) c = a + b - p, has_c = true;
          glm::vec3 sum = 0.5625f * p;
          float total = 0.5625f;
          if (has_a) sum += 0.1875f * a, total += 0.1875f;
          if (has_b) sum += 0.1875f * b, total += 0.1875f;
          if (has_c) sum += 0.0625f * c, total += 0.0625f;
          sum = glm::max(sum, glm::vec3(0.0f));  // extrapolation never makes light negative
          const size_t t = size_t(y) * fine.width + x;
          fine.light[t] = fine.at(t) + sum / total;
          fine.filled[t] = 1;
        }
      }
    });
  }
  const Level& pixels = levels_[0];
  tbb::parallel_for(tbb::blocked_range<size_t>(0, image.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) image[i] = pixels.at(i);
  });
}

template <typename Sample>
void MultiresolutionBuffer::sum_levels(Sample&& sample, std::vector<glm::vec3>& out) const {
  for (uint32_t y = 0; y < height_; ++y) {
    for (uint32_t x = 0; x < width_; ++x) {
      glm::vec3 sum(0.0f);
      for (uint32_t k = 0; k < levels_.size(); ++k) sum += sample(levels_[k], k, x, y);
      out[size_t(y) * width_ + x] = sum;
    }
  }
}

void MultiresolutionBuffer::upsample_nearest(std::vector<glm::vec3>& image) const {
  sum_levels([](const Level& l, uint32_t k, uint32_t x,
                uint32_t y) { return l.at(size_t(y >> k) * l.width + (x >> k)); },
             image);
}

void MultiresolutionBuffer::upsample_bilinear(std::vector<glm::vec3>& image) const {
  sum_levels(
      [](const Level& l, uint32_t k, uint32_t x, uint32_t y) {
        // The pixel centre in this level's texel coordinates (texel centres at +0.5).
        const float scale = 1.0f / float(1u << k);
        const float fx = std::clamp((float(x) + 0.5f) * scale - 0.5f, 0.0f, float(l.width - 1));
        const float fy = std::clamp((float(y) + 0.5f) * scale - 0.5f, 0.0f, float(l.height - 1));
        const uint32_t x0 = uint32_t(fx), y0 = uint32_t(fy);
        const uint32_t x1 = std::min(x0 + 1, l.width - 1), y1 = std::min(y0 + 1, l.height - 1);
        const float ax = fx - float(x0), ay = fy - float(y0);
        const auto at = [&](uint32_t u, uint32_t v) { return l.at(size_t(v) * l.width + u); };
        return (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) +
               (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
      },
      image);
}

void render_subsplats(const SubsplatSet& set, const MinMaxMipmap& mipmap, const EyeGBuffer& gbuffer,
                      const DiscontinuityTest& test, const SurfaceLight& light,
                      MultiresolutionBuffer& buffer) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, set.subsplats.size(), 64), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Subsplat& s = set.subsplats[i];
      buffer.add(s, light(mipmap.point(gbuffer, s.level, s.x, s.y, test)));  // own texels
    }
  });
}

}  // namespace bakegi
