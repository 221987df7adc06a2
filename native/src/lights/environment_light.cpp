#include "lights/environment_light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "util/luminance.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Index of the interval [cdf[k], cdf[k+1]) holding u (cdf ascending from 0 to 1), and u's
// place in it in [0, 1); empty intervals are never chosen.
size_t find_interval(const float* cdf, size_t intervals, float u, float& place) {
  const float* end = cdf + intervals + 1;
  const float* at = std::upper_bound(cdf, end, u);
  size_t k = size_t(std::clamp<std::ptrdiff_t>(at - cdf - 1, 0, std::ptrdiff_t(intervals) - 1));
  while (k + 1 < intervals && !(cdf[k + 1] > cdf[k])) ++k;
  const float width = cdf[k + 1] - cdf[k];
  place = width > 0.0f ? std::clamp((u - cdf[k]) / width, 0.0f, 0.99999994f) : 0.5f;
  return k;
}

// sin(theta) of row j's centre: the solid angle its texels cover, per unit of (u, v).
double row_sine(uint32_t j, uint32_t height) {
  return std::sin(std::numbers::pi * (double(j) + 0.5) / double(height));
}

}  // namespace

EnvironmentLight::EnvironmentLight(const WorldTexture& world, const std::vector<Texture>& textures)
    : texture_(textures.at(world.texture)),
      scale_(world.scale),
      rotation_(world.rotation),
      width_(texture_.width),
      height_(texture_.height) {
  const size_t w = width_, h = height_;
  std::vector<float> texel_luminance(w * h);
  glm::dvec3 weighted_sum(0.0);
  double sine_sum = 0.0;
  for (size_t j = 0; j < h; ++j) {
    const double sine = row_sine(uint32_t(j), height_);
    for (size_t i = 0; i < w; ++i) {
      const glm::vec3 radiance = scale_ * texture_.texel(j * w + i);
      texel_luminance[j * w + i] = std::max(0.0f, float(luminance(radiance)));
      weighted_sum += sine * glm::dvec3(radiance);
      sine_sum += sine;
    }
  }
  mean_radiance_ = glm::vec3(weighted_sum / std::max(sine_sum, 1e-30));

  // Weights: the largest luminance of the 3 x 3 texels around (wrapping in u, clamped in v)
  // times sin theta; rows and columns as cumulative sums.
  row_cdf_.assign(h + 1, 0.0f);
  column_cdf_.assign(h * (w + 1), 0.0f);
  texel_pdf_.assign(w * h, 0.0f);
  std::vector<double> row_weight(h, 0.0), weight(w);
  for (size_t j = 0; j < h; ++j) {
    const double sine = row_sine(uint32_t(j), height_);
    double sum = 0.0;
    for (size_t i = 0; i < w; ++i) {
      float largest = 0.0f;
      for (size_t dj = (j > 0 ? j - 1 : j); dj <= std::min(h - 1, j + 1); ++dj) {
        for (int di = -1; di <= 1; ++di) {
          const size_t column = (i + w + size_t(di + 1) - 1) % w;
          largest = std::max(largest, texel_luminance[dj * w + column]);
        }
      }
      weight[i] = double(largest) * sine;
      sum += weight[i];
    }
    row_weight[j] = sum;
    float* cdf = &column_cdf_[j * (w + 1)];
    double running = 0.0;
    for (size_t i = 0; i < w; ++i) {
      running += weight[i];
      cdf[i + 1] = sum > 0.0 ? float(running / sum) : float(i + 1) / float(w);
    }
    cdf[w] = 1.0f;
    for (size_t i = 0; i < w; ++i) texel_pdf_[j * w + i] = float(weight[i]);
  }
  double total = 0.0;
  for (size_t j = 0; j < h; ++j) total += row_weight[j];
  black_ = !(total > 0.0);
  if (black_) return;
  double running = 0.0;
  for (size_t j = 0; j < h; ++j) {
    running += row_weight[j];
    row_cdf_[j + 1] = float(running / total);
  }
  row_cdf_[h] = 1.0f;
  // Density in (u, v) over the unit square: the texel's probability over its area 1 / (w h).
  const double to_density = double(w) * double(h) / total;
  for (float& p : texel_pdf_) p = float(double(p) * to_density);
}

size_t EnvironmentLight::bytes() const {
  return (row_cdf_.size() + column_cdf_.size() + texel_pdf_.size()) * sizeof(float);
}

EnvironmentLight::Place EnvironmentLight::place_of(const glm::vec3& direction) const {
  const glm::vec3 d = rotation_ * direction;
  const float u = 0.5f - std::atan2(d.y, d.x) * (0.5f * kInvPi);
  const float v = 0.5f + std::asin(std::clamp(d.z, -1.0f, 1.0f)) * kInvPi;
  return {{u, v}, std::sqrt(std::max(0.0f, 1.0f - d.z * d.z))};
}

float EnvironmentLight::density_at(const Place& place) const {
  if (black_ || !(place.sine > 0.0f)) return 0.0f;
  const glm::vec2& uv = place.uv;
  const size_t i = std::min(size_t(width_ - 1), size_t((uv.x - std::floor(uv.x)) * float(width_)));
  const size_t j = std::min(size_t(height_ - 1), size_t(std::clamp(uv.y, 0.0f, 1.0f) * height_));
  return texel_pdf_[j * width_ + i] / (2.0f * kPi * kPi * place.sine);
}

glm::vec3 EnvironmentLight::lookup(const glm::vec2& uv) const {
  const double x = (double(uv.x) - std::floor(double(uv.x))) * width_ - 0.5;
  const double y = std::clamp(double(uv.y), 0.0, 1.0) * height_ - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const float fx = float(x - x0), fy = float(y - y0);
  const auto column = [&](double i) {
    const int64_t m = int64_t(i) % int64_t(width_);
    return size_t(m < 0 ? m + width_ : m);
  };
  const auto row = [&](double j) {
    return size_t(std::clamp<int64_t>(int64_t(j), 0, int64_t(height_) - 1));
  };
  const size_t i0 = column(x0), i1 = column(x0 + 1), j0 = row(y0), j1 = row(y0 + 1);
  const glm::vec3 bottom =
      glm::mix(texture_.texel(j0 * width_ + i0), texture_.texel(j0 * width_ + i1), fx);
  const glm::vec3 top =
      glm::mix(texture_.texel(j1 * width_ + i0), texture_.texel(j1 * width_ + i1), fx);
  return scale_ * glm::mix(bottom, top, fy);
}

glm::vec3 EnvironmentLight::radiance(const glm::vec3& direction) const {
  return lookup(place_of(direction).uv);
}

float EnvironmentLight::pdf(const glm::vec3& direction) const {
  return density_at(place_of(direction));
}

glm::vec3 EnvironmentLight::radiance(const glm::vec3& direction, float& pdf) const {
  const Place place = place_of(direction);
  pdf = density_at(place);
  return lookup(place.uv);
}

bool EnvironmentLight::sample(float u1, float u2, LightSample& out) const {
  if (black_) return false;
  float row_place = 0.0f, column_place = 0.0f;
  const size_t j = find_interval(row_cdf_.data(), height_, u1, row_place);
  const size_t i = find_interval(&column_cdf_[j * (width_ + 1)], width_, u2, column_place);
  const float density = texel_pdf_[j * width_ + i];
  if (!(density > 0.0f)) return false;
  const float u = (float(i) + column_place) / float(width_);
  const float v = (float(j) + row_place) / float(height_);
  const float theta = kPi * (1.0f - v), phi = kPi - 2.0f * kPi * u;
  const float sine = std::sin(theta);
  if (!(sine > 0.0f)) return false;
  const glm::vec3 local(sine * std::cos(phi), sine * std::sin(phi), std::cos(theta));
  // The rotation is orthonormal: its transpose turns the image's frame back into the world.
  out.direction = glm::normalize(glm::transpose(rotation_) * local);
  out.distance = std::numeric_limits<float>::infinity();
  out.pdf = density / (2.0f * kPi * kPi * sine);
  out.contribution = lookup({u, v}) / out.pdf;
  return true;
}

}  // namespace bakegi
