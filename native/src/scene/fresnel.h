// The exact (unpolarized) Fresnel reflectance of a dielectric interface, for glass that passes
// less light at grazing angles (scene/passing_surfaces.h).
#pragma once

#include <algorithm>
#include <cmath>

namespace bakegi {

// Reflectance at |cos theta| = c of an interface between air and index eta (eta >= 1).
inline float fresnel_dielectric(float c, float eta) {
  c = std::clamp(c, 0.0f, 1.0f);
  const float g = std::sqrt(eta * eta - 1.0f + c * c);
  const float a = (g - c) / (g + c);
  const float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
  return 0.5f * a * a * (1.0f + b * b);
}

// Its cosine-weighted hemispherical average, 2 x the integral of F(c) c over c in [0, 1]
// (midpoint rule on 512 points; 0.0918 for eta = 1.5), as the add-on's
// fresnel_hemispherical_average computes it.
inline float fresnel_hemispherical_average(float eta) {
  constexpr int kCount = 512;
  double total = 0.0;
  for (int i = 0; i < kCount; ++i) {
    const float c = (float(i) + 0.5f) / kCount;
    total += double(fresnel_dielectric(c, eta)) * c;
  }
  return float(2.0 * total / kCount);
}

}  // namespace bakegi
