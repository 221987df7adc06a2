// Compressing the Irradiance Vector Grid (Pacanowski et al. 2008, §3.3). A hemisphere's 3x3
// matrix M = (I^R | I^G | I^B) becomes a direction d and a colour c:
//   d = (I^R + I^G + I^B) / |I^R + I^G + I^B|,   c_k = (I^k . delta) / (d . delta),
// and is read back as I^k = c_k d, which keeps the RGB irradiance exactly for a normal along
// delta (M delta = c (d . delta)). Quantized, d takes 24 bits (8 per coordinate) and c 32
// bits in the shared-exponent R9G9B9E5 format (GL_EXT_texture_shared_exponent, the format
// WebGL2 and every GPU sample as a float texture): 7 bytes per hemisphere instead of 36.
// c is computed from the quantized d, so the along-delta exactness survives d's rounding.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "grid/irradiance_vector_grid.h"

namespace bakegi {

// Shared-exponent RGB: 9-bit mantissas, a 5-bit exponent (bias 15). Negative and NaN
// channels encode as 0, values above kRgb9e5Max as kRgb9e5Max.
inline constexpr float kRgb9e5Max = 65408.0f;
uint32_t encode_rgb9e5(const glm::vec3& rgb);
glm::vec3 decode_rgb9e5(uint32_t packed);

// A unit direction on 8 bits per coordinate, (x + 1) * 127.5 rounded; decoded and
// renormalized (a zero decodes as +z).
struct PackedDirection {
  uint8_t x, y, z;
};
PackedDirection encode_direction(const glm::vec3& unit_direction);
glm::vec3 decode_direction(const PackedDirection& packed);

struct QuantizedHemisphere {
  PackedDirection direction;
  uint32_t color = 0;  // R9G9B9E5
};

// Hemisphere h's matrix, factored and quantized; and back.
QuantizedHemisphere quantize_hemisphere(const glm::mat3& m, int h);
glm::mat3 dequantize_hemisphere(const QuantizedHemisphere& q);

// The factorization alone, in floats (what quantization adds on top is rounding).
struct FactoredHemisphere {
  glm::vec3 direction;
  glm::vec3 color;
};
FactoredHemisphere factor_hemisphere(const glm::mat3& m, int h);
inline glm::mat3 expand_hemisphere(const glm::vec3& direction, const glm::vec3& color) {
  return glm::mat3(color.x * direction, color.y * direction, color.z * direction);
}

// The grid as a client reads it after quantization (every hemisphere quantized and expanded).
IrradianceVectorGrid quantized_grid(const IrradianceVectorGrid& grid);

}  // namespace bakegi
