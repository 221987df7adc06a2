#include "lightmap/lightmap_padding.h"

#include "util/error.h"

namespace bakegi {

RgbImage resolve_texels(const TexelSamples& samples, const glm::vec3* values,
                        std::vector<uint8_t>& filled) {
  const size_t texels = size_t(samples.width) * samples.height;
  RgbImage image;
  image.width = samples.width;
  image.height = samples.height;
  // Sums are accumulated in place (floats: a texel has a handful of samples), keeping the
  // footprint at 16 bytes per texel for large maps.
  image.pixels.assign(texels, glm::vec3(0.0f));
  std::vector<float> weight_sum(texels, 0.0f);
  for (size_t i = 0; i < samples.size(); ++i) {
    const uint32_t texel = samples.texel[i];
    if (texel >= texels) throw Error(BAKEGI_ERROR_INTERNAL, "sample texel out of range");
    image.pixels[texel] += samples.weight[i] * values[i];
    weight_sum[texel] += samples.weight[i];
  }
  filled.assign(texels, 0);
  for (size_t t = 0; t < texels; ++t) {
    if (weight_sum[t] > 0) {
      image.pixels[t] /= weight_sum[t];
      filled[t] = 1;
    }
  }
  return image;
}

void dilate_texels(RgbImage& image, std::vector<uint8_t>& filled, uint32_t passes) {
  const int width = int(image.width), height = int(image.height);
  if (filled.size() != image.pixels.size() || image.pixels.size() != size_t(width) * height) {
    throw Error(BAKEGI_ERROR_INTERNAL, "dilate_texels: mask and image sizes differ");
  }
  std::vector<uint32_t> frontier;  // unfilled texels touching a filled one, this round
  std::vector<glm::vec3> frontier_values;
  for (uint32_t pass = 0; pass < passes; ++pass) {
    frontier.clear();
    frontier_values.clear();
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const size_t t = size_t(y) * width + x;
        if (filled[t]) continue;
        glm::vec3 sum(0.0f);
        float weight = 0.0f;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
            const size_t n = size_t(ny) * width + nx;
            if (!filled[n]) continue;
            const float w = dx != 0 && dy != 0 ? 0.5f : 1.0f;
            sum += w * image.pixels[n];
            weight += w;
          }
        }
        if (weight > 0) {
          frontier.push_back(uint32_t(t));
          frontier_values.push_back(sum / weight);
        }
      }
    }
    if (frontier.empty()) break;  // everything reachable is filled
    for (size_t i = 0; i < frontier.size(); ++i) {
      image.pixels[frontier[i]] = frontier_values[i];
      filled[frontier[i]] = 1;
    }
  }
}

}  // namespace bakegi
