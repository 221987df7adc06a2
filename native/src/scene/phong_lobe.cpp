#include "scene/phong_lobe.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bakegi {

double phong_directional_albedo(double exponent, double mu) {
  mu = std::clamp(mu, 0.0, 1.0);
  const double sin_mu = std::sqrt(1.0 - mu * mu);
  // Substitute t = cos^(n+1) α: cos^n α sin α dα = dt / (n + 1), so the lobe's measure is
  // uniform in t and the quadrature needs no knowledge of how narrow the lobe is.
  constexpr int kSteps = 4096;
  double sum = 0.0;
  for (int k = 0; k < kSteps; ++k) {
    const double t = (k + 0.5) / kSteps;
    const double cos_alpha = std::pow(t, 1.0 / (exponent + 1.0));
    const double sin_alpha = std::sqrt(std::max(0.0, 1.0 - cos_alpha * cos_alpha));
    // ⟨N|ω⟩ = a + b cos φ around the mirror direction; its positive part over φ in [0, 2π).
    const double a = cos_alpha * mu, b = sin_alpha * sin_mu;
    if (a >= b) {
      sum += 2.0 * std::numbers::pi * a;
    } else if (a > -b) {
      const double phi0 = std::acos(-a / b);
      sum += 2.0 * (a * phi0 + b * std::sin(phi0));
    }
  }
  return (exponent + 2.0) / (2.0 * std::numbers::pi * (exponent + 1.0)) * sum / kSteps;
}

double phong_hemispherical_albedo(double exponent) {
  // Midpoint rule in μ²: 2 ∫ A(μ) μ dμ = ∫ A(√s) ds over s in [0, 1]; A is smooth in s.
  constexpr int kSteps = 64;
  double sum = 0.0;
  for (int k = 0; k < kSteps; ++k) {
    sum += phong_directional_albedo(exponent, std::sqrt((k + 0.5) / kSteps));
  }
  return sum / kSteps;
}

}  // namespace bakegi
