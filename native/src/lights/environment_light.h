// The world's light from an equirectangular environment image (an HDRI sky), as Cycles'
// Environment Texture node maps it: a unit direction d, turned into the image's frame by the
// world's rotation (d' = R d), reads the image at
//   u = 0.5 - atan2(d'.y, d'.x) / (2 pi),   v = 0.5 + asin(d'.z) / pi
// (Cycles' direction_to_equirectangular; v = 0 is the image's bottom row, the nadir), with
// bilinear interpolation between texel centres, wrapping around in u. Radiance = scale x the
// image, W/(m^2 sr).
//
// Light sampling draws a texel with probability proportional to its luminance times the solid
// angle it covers (sin theta; pbrt's piecewise-constant 2D distribution over the image) and
// a uniform point in it, so a small bright sun in the image is found by the shadow rays, not
// only by the BSDF's rays; the two are combined by multiple importance sampling. A texel's
// weight is the largest luminance of its 3 x 3 neighbourhood: bilinear lookup spreads a bright
// texel into its neighbours, which must not get density 0.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "lights/light_sample.h"
#include "scene/scene.h"

namespace bakegi {

class EnvironmentLight {
 public:
  // `world` must name a texture of `textures` (checked by scene validation).
  EnvironmentLight(const WorldTexture& world, const std::vector<Texture>& textures);

  // Radiance arriving from the unit direction d (towards the sky).
  glm::vec3 radiance(const glm::vec3& direction) const;
  // Solid-angle density of sample() for direction d.
  float pdf(const glm::vec3& direction) const;
  // Both at once (a ray that escaped: its radiance and MIS weight), the direction mapped once.
  glm::vec3 radiance(const glm::vec3& direction, float& pdf) const;
  // A direction towards the sky by the image's light; false where the image is black.
  bool sample(float u1, float u2, LightSample& out) const;
  // The mean radiance over the sphere (what methods that take a constant world use).
  const glm::vec3& mean_radiance() const { return mean_radiance_; }
  // Heap bytes held (the distribution; the image stays in the scene's textures).
  size_t bytes() const;

 private:
  // Where a direction falls in the image, and sin theta there (the solid angle per (u, v)).
  struct Place {
    glm::vec2 uv;
    float sine;
  };
  Place place_of(const glm::vec3& direction) const;
  float density_at(const Place& place) const;
  glm::vec3 lookup(const glm::vec2& uv) const;

  Texture texture_;  // a copy: it shares the scene's texels, and outlives any copy of the scene
  glm::vec3 scale_;
  glm::mat3 rotation_;  // world direction -> the image's frame
  uint32_t width_, height_;
  // Row j's weight (luminance x sin theta, summed over the row) as a cumulative distribution
  // over the rows, and in each row the cumulative distribution over its texels; both end at 1.
  std::vector<float> row_cdf_;     // height_ + 1
  std::vector<float> column_cdf_;  // height_ x (width_ + 1)
  std::vector<float> texel_pdf_;   // per texel: probability / (texel's area in (u, v)) = p W H
  glm::vec3 mean_radiance_{0.0f};
  bool black_ = true;
};

}  // namespace bakegi
