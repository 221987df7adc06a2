// The BSDF of a material at one surface point, as the path tracer samples it: a diffuse lobe
// ρ_d/π plus the optional Phong lobe (scene/phong_lobe.h), both on the side the viewer is.
// Directions point away from the surface; the normal is the shading normal on the viewer's
// side. Sampling picks a lobe with probability proportional to its mean reflectance, then
// weighs by the density of the whole mixture (one-sample MIS between the lobes), so the
// sample weight f cos / pdf stays bounded by about max(ρ_d / P_d, 2 ρ_g / P_g).
#pragma once

#include <glm/glm.hpp>

#include "scene/phong_lobe.h"
#include "util/sampling.h"

namespace bakegi {

struct BsdfSample {
  glm::vec3 direction{0.0f};  // unit, away from the surface
  glm::vec3 weight{0.0f};     // f cos / pdf
  float pdf = 0.0f;           // solid-angle density of the mixture
};

class SurfaceBsdf {
 public:
  SurfaceBsdf(const glm::vec3& normal, const glm::vec3& to_viewer, const glm::vec3& diffuse,
              const glm::vec3& glossy, float exponent)
      : normal_(normal),
        axis_(mirror_direction(normal, to_viewer)),
        diffuse_(diffuse),
        glossy_(glossy),
        lobe_{exponent} {
    const float d = mean(diffuse), g = mean(glossy);
    glossy_probability_ = d + g > 0.0f ? g / (d + g) : 0.0f;
  }

  // f(ω) ⟨n|ω⟩₊ for a unit direction ω towards the light.
  glm::vec3 reflected(const glm::vec3& to_light) const {
    const float cosine = glm::dot(normal_, to_light);
    if (!(cosine > 0.0f)) return glm::vec3(0.0f);
    return (diffuse_ * kInvPi + glossy_ * lobe_.value(glm::dot(axis_, to_light))) * cosine;
  }

  // Density with which sample() draws ω.
  float pdf(const glm::vec3& to_light) const {
    const float cosine = glm::dot(normal_, to_light);
    if (!(cosine > 0.0f)) return 0.0f;
    return (1.0f - glossy_probability_) * cosine * kInvPi +
           glossy_probability_ * lobe_.pdf(glm::dot(axis_, to_light));
  }

  // u0 picks the lobe, (u1, u2) the direction. A direction below the surface comes back
  // with pdf 0 (the path ends).
  BsdfSample sample(float u0, float u1, float u2) const {
    BsdfSample s;
    if (u0 < glossy_probability_) {
      s.direction = lobe_.sample(axis_, u1, u2);
    } else {
      s.direction = Frame(normal_).to_world(sample_cosine_hemisphere(u1, u2));
    }
    s.pdf = pdf(s.direction);
    if (s.pdf > 0.0f) s.weight = reflected(s.direction) / s.pdf;
    return s;
  }

 private:
  static float mean(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

  glm::vec3 normal_, axis_;
  glm::vec3 diffuse_, glossy_;
  PhongLobe lobe_;
  float glossy_probability_ = 0.0f;
};

}  // namespace bakegi
