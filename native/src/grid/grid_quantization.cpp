#include "grid/grid_quantization.h"

#include <algorithm>
#include <cmath>

namespace bakegi {

namespace {

constexpr int kMantissaBits = 9;
constexpr int kExponentBias = 15;
constexpr int kMaxExponent = 31;

// Below this, d . delta is too small to divide by: the light grazes the hemisphere's rim,
// and its matrix is stored along delta itself (the along-delta irradiance is still kept).
constexpr float kMinAlongAxis = 1e-3f;

float clamp_channel(float v) {
  if (!(v > 0.0f)) return 0.0f;  // negative and NaN
  return std::min(v, kRgb9e5Max);
}

}  // namespace

uint32_t encode_rgb9e5(const glm::vec3& rgb) {
  const float r = clamp_channel(rgb.x), g = clamp_channel(rgb.y), b = clamp_channel(rgb.z);
  const float largest = std::max({r, g, b});
  if (largest == 0.0f) return 0;
  int exponent =
      std::max(-kExponentBias - 1, int(std::floor(std::log2(largest)))) + 1 + kExponentBias;
  float scale = std::ldexp(1.0f, exponent - kExponentBias - kMantissaBits);
  if (int(std::floor(largest / scale + 0.5f)) == (1 << kMantissaBits)) {
    ++exponent;
    scale *= 2.0f;
  }
  exponent = std::clamp(exponent, 0, kMaxExponent);
  const auto mantissa = [&](float v) {
    return uint32_t(std::min(511.0f, std::floor(v / scale + 0.5f)));
  };
  return mantissa(r) | (mantissa(g) << 9) | (mantissa(b) << 18) | (uint32_t(exponent) << 27);
}

glm::vec3 decode_rgb9e5(uint32_t packed) {
  const int exponent = int(packed >> 27);
  const float scale = std::ldexp(1.0f, exponent - kExponentBias - kMantissaBits);
  return glm::vec3(float(packed & 511u), float((packed >> 9) & 511u),
                   float((packed >> 18) & 511u)) *
         scale;
}

PackedDirection encode_direction(const glm::vec3& d) {
  const auto one = [](float x) {
    return uint8_t(std::clamp(std::lround((std::clamp(x, -1.0f, 1.0f) + 1.0f) * 127.5f), 0l, 255l));
  };
  return {one(d.x), one(d.y), one(d.z)};
}

glm::vec3 decode_direction(const PackedDirection& p) {
  const glm::vec3 d(float(p.x) / 127.5f - 1.0f, float(p.y) / 127.5f - 1.0f,
                    float(p.z) / 127.5f - 1.0f);
  const float length = glm::length(d);
  return length > 0.0f ? d / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

namespace {

// c_k = (I^k . delta) / (d . delta) for a given unit direction d (d . delta > 0).
glm::vec3 color_along(const glm::mat3& m, const glm::vec3& axis, const glm::vec3& d) {
  const float along = glm::dot(d, axis);
  return glm::vec3(glm::dot(m[0], axis), glm::dot(m[1], axis), glm::dot(m[2], axis)) / along;
}

glm::vec3 mean_direction(const glm::mat3& m, const glm::vec3& axis) {
  const glm::vec3 sum = m[0] + m[1] + m[2];
  const float length = glm::length(sum);
  if (!(length > 0.0f) || !std::isfinite(length)) return axis;
  const glm::vec3 d = sum / length;
  return glm::dot(d, axis) >= kMinAlongAxis ? d : axis;
}

}  // namespace

FactoredHemisphere factor_hemisphere(const glm::mat3& m, int h) {
  const glm::vec3 axis = hemisphere_axis(h);
  const glm::vec3 d = mean_direction(m, axis);
  return {d, glm::max(color_along(m, axis, d), glm::vec3(0.0f))};
}

QuantizedHemisphere quantize_hemisphere(const glm::mat3& m, int h) {
  const glm::vec3 axis = hemisphere_axis(h);
  PackedDirection packed = encode_direction(mean_direction(m, axis));
  glm::vec3 d = decode_direction(packed);
  if (glm::dot(d, axis) < kMinAlongAxis) {  // rounding pushed it to the rim
    packed = encode_direction(axis);
    d = decode_direction(packed);
  }
  return {packed, encode_rgb9e5(color_along(m, axis, d))};
}

glm::mat3 dequantize_hemisphere(const QuantizedHemisphere& q) {
  return expand_hemisphere(decode_direction(q.direction), decode_rgb9e5(q.color));
}

IrradianceVectorGrid quantized_grid(const IrradianceVectorGrid& grid) {
  IrradianceVectorGrid out = grid;
  for (size_t v = 0; v < grid.vertex_count(); ++v) {
    for (int h = 0; h < kGridHemispheres; ++h) {
      out.at(v, h) = dequantize_hemisphere(quantize_hemisphere(grid.at(v, h), h));
    }
  }
  return out;
}

}  // namespace bakegi
