#include "scene/scene.h"

#include <algorithm>
#include <cmath>

namespace bakegi {

namespace {

// Bilinear lookup with repeat wrapping; texel (i, j) has its centre at ((i+0.5)/w,
// (j+0.5)/h), as in Cycles' linear image interpolation.
glm::vec3 sample_bilinear(const Texture& texture, glm::vec2 uv) {
  const double w = texture.width, h = texture.height;
  const double x = (uv.x - std::floor(double(uv.x))) * w - 0.5;
  const double y = (uv.y - std::floor(double(uv.y))) * h - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const float fx = float(x - x0), fy = float(y - y0);
  auto wrap = [](double i, uint32_t n) {
    const int64_t m = int64_t(i) % int64_t(n);
    return uint32_t(m < 0 ? m + n : m);
  };
  const uint32_t i0 = wrap(x0, texture.width), i1 = wrap(x0 + 1, texture.width);
  const uint32_t j0 = wrap(y0, texture.height), j1 = wrap(y0 + 1, texture.height);
  const auto blend = [&](const auto& texel) {
    const glm::vec3 bottom = glm::mix(texel(i0, j0), texel(i1, j0), fx);
    const glm::vec3 top = glm::mix(texel(i0, j1), texel(i1, j1), fx);
    return glm::mix(bottom, top, fy);
  };
  const size_t width = texture.width;
  if (const TexelPalette* palette = texture.palette()) {
    return blend([&](uint32_t i, uint32_t j) { return palette->texel(size_t(j) * width + i); });
  }
  const glm::vec3* texels = texture.float_texels();
  return blend([&](uint32_t i, uint32_t j) { return texels[size_t(j) * width + i]; });
}

}  // namespace

void Texture::set_texels(std::vector<glm::vec3> values, bool allow_palette) {
  // Under 128 texels the palette's 1 KB of values outweighs the floats.
  palette_ = allow_palette && values.size() >= 128 ? make_texel_palette(values) : nullptr;
  floats_ = palette_ ? nullptr : std::make_shared<const std::vector<glm::vec3>>(std::move(values));
}

std::vector<glm::vec3> Texture::texels() const {
  if (floats_) return *floats_;
  std::vector<glm::vec3> out(texel_count());
  for (size_t i = 0; i < out.size(); ++i) out[i] = texel(i);
  return out;
}

bool Texture::operator==(const Texture& other) const {
  if (width != other.width || height != other.height) return false;
  if (floats_ == other.floats_ && palette_ == other.palette_) return true;
  if (texel_count() != other.texel_count()) return false;
  for (size_t i = 0, n = texel_count(); i < n; ++i) {
    if (texel(i) != other.texel(i)) return false;
  }
  return true;
}

glm::vec3 Scene::albedo_at(const Triangle& t, float b1, float b2) const {
  const Material& material = material_of(t);
  if (material.albedo_texture == BAKEGI_NO_TEXTURE) return material.albedo;
  const Texture& texture = description.textures[material.albedo_texture];
  const glm::vec2 uv = (1.0f - b1 - b2) * t.uv[0] + b1 * t.uv[1] + b2 * t.uv[2];
  // A reflectance above 1 would create energy; textures are checked to lie in [0,1] up to
  // rounding, which the clamp removes.
  return glm::clamp(material.albedo * sample_bilinear(texture, uv), 0.0f, 1.0f);
}

glm::vec3 Scene::albedo_at(uint32_t triangle, float b1, float b2) const {
  const Material& material = material_of(triangle);
  if (material.albedo_texture == BAKEGI_NO_TEXTURE) return material.albedo;
  return albedo_at(triangles[triangle], b1, b2);
}

float presence_at(const Material& material, const std::vector<Texture>& textures, const Triangle& t,
                  float b1, float b2) {
  float present = material.opacity;
  if (material.opacity_texture != BAKEGI_NO_TEXTURE) {
    const Texture& texture = textures[material.opacity_texture];
    const glm::vec2 uv = (1.0f - b1 - b2) * t.uv[0] + b1 * t.uv[1] + b2 * t.uv[2];
    present *= glm::clamp(sample_bilinear(texture, uv).x, 0.0f, 1.0f);
  }
  return present;
}

glm::vec3 Scene::emission_at(const Triangle& t, float b1, float b2) const {
  const Material& material = material_of(t);
  if (material.emission_texture == BAKEGI_NO_TEXTURE) return material.emission;
  const Texture& texture = description.textures[material.emission_texture];
  const glm::vec2 uv = (1.0f - b1 - b2) * t.uv[0] + b1 * t.uv[1] + b2 * t.uv[2];
  return material.emission * sample_bilinear(texture, uv);
}

}  // namespace bakegi
