// The glossy lobe of materials: the normalized modified Phong BRDF (Lafortune & Willems 1994,
// "Using the modified Phong reflectance model for physically based rendering"):
//
//   f_g(ω_i, ω_o) = ρ_g (n + 2) / (2π) cos^n α,   α = angle between ω_i and the mirror
//                                                     direction of ω_o (0 for α > 90°)
//
// with both directions pointing away from the surface. The factor (n + 2) / (2π) makes the
// directional albedo exactly ρ_g at normal incidence and less elsewhere (the lobe is cut by
// the horizon and weighted by a smaller cosine): energy conserving for every n ≥ 0. n = 0
// is a second Lambertian lobe ρ_g/π; n ≳ 1000 is a near mirror (half width ≈ √(2/n) rad).
// Reciprocal: α is the same angle seen from either side.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "util/sampling.h"

namespace bakegi {

// The mirror image of the unit direction v about the unit normal (both pointing away).
inline glm::vec3 mirror_direction(const glm::vec3& normal, const glm::vec3& v) {
  return 2.0f * glm::dot(normal, v) * normal - v;
}

struct PhongLobe {
  float exponent = 0.0f;

  // f_g / ρ_g for cos α (the cosine between a direction and the lobe's axis).
  float value(float cos_alpha) const {
    if (!(cos_alpha > 0.0f)) return 0.0f;
    return (exponent + 2.0f) * (0.5f * kInvPi) * std::pow(std::min(cos_alpha, 1.0f), exponent);
  }
  // Solid-angle density of sample(): the lobe shape cos^n α normalized over the sphere,
  // (n + 1) / (2π) cos^n α (directions below the surface included; callers discard them).
  float pdf(float cos_alpha) const {
    if (!(cos_alpha > 0.0f)) return 0.0f;
    return (exponent + 1.0f) * (0.5f * kInvPi) * std::pow(std::min(cos_alpha, 1.0f), exponent);
  }
  // A direction around the unit `axis` with density pdf(): cos α = u1^(1/(n+1)).
  glm::vec3 sample(const glm::vec3& axis, float u1, float u2) const {
    const float cos_alpha = std::pow(1.0f - u1, 1.0f / (exponent + 1.0f));  // u1 < 1
    const float sin_alpha = std::sqrt(std::max(0.0f, 1.0f - cos_alpha * cos_alpha));
    const float phi = 2.0f * kPi * u2;
    const glm::vec3 local(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), cos_alpha);
    return glm::normalize(Frame(axis).to_world(local));
  }
};

// Directional albedo of the lobe divided by ρ_g, for a direction at cosine `mu` to the
// normal (by reciprocity the same for light arriving from there and for a viewer there):
//   A(μ) = ∫ (n + 2)/(2π) cos^n α ⟨N|ω⟩₊ dω,   α measured from the mirror direction.
// A(1) = 1, A decreases towards grazing (≈ μ (n+2)/(n+1) for large n). Deterministic
// quadrature (the azimuth in closed form, 4096 points along the lobe), error < 1e-5.
double phong_directional_albedo(double exponent, double mu);

// The cosine-weighted hemispherical albedo of the normalized Phong lobe of exponent n, per
// unit ρ_g: 2 ∫ A(μ) μ dμ with A from phong_directional_albedo. What a uniform field loses to
// the lobe, so folding the lobe into the diffuse albedo conserves energy in that field
// (antiradiance's wide lobes, every lobe of the diffuse-only meshless method).
double phong_hemispherical_albedo(double exponent);

}  // namespace bakegi
