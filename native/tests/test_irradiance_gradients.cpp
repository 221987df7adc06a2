// Irradiance gradients from a stratified gather (solvers/pathtrace/irradiance_gradients.h)
// against a case with a closed form: a unit-radiance square above the point, whose E/π is
// Lambert's polygon formula; the gradients it is compared with are that formula's central
// differences.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "solvers/pathtrace/irradiance_gradients.h"
#include "util/pcg32.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

// The square |x - cx|, |y - cy| <= h at height z = top, radiance 1 (of `colour`).
struct Square {
  glm::dvec3 centre{0.0, 0.0, 1.0};
  double half = 0.5;

  std::array<glm::dvec3, 4> corners() const {
    return {centre + glm::dvec3(-half, -half, 0), centre + glm::dvec3(half, -half, 0),
            centre + glm::dvec3(half, half, 0), centre + glm::dvec3(-half, half, 0)};
  }
  // E/π at x with normal n (the square wholly above x's tangent plane): Lambert's formula.
  double irradiance_over_pi(const glm::dvec3& x, const glm::dvec3& n) const {
    const auto c = corners();
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) {
      const glm::dvec3 a = glm::normalize(c[size_t(i)] - x);
      const glm::dvec3 b = glm::normalize(c[size_t((i + 1) % 4)] - x);
      const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
      sum += angle * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return std::abs(sum) / (2.0 * M_PI);
  }
  // The distance along `d` from x to the square, +inf if it misses.
  float hit(const glm::dvec3& x, const glm::dvec3& d) const {
    if (!(d.z > 0.0)) return std::numeric_limits<float>::infinity();
    const double t = (centre.z - x.z) / d.z;
    const glm::dvec3 p = x + t * d;
    if (std::abs(p.x - centre.x) > half || std::abs(p.y - centre.y) > half) {
      return std::numeric_limits<float>::infinity();
    }
    return float(t);
  }
};

IrradianceGather gather(const Square& square, const glm::dvec3& x, const glm::dvec3& n,
                        int samples) {
  const Frame frame{glm::vec3(n)};
  HemisphereCells cells;
  Pcg32 rng(17, 3);
  const glm::vec3 colour(1.0f, 0.5f, 0.25f);
  for (int s = 0; s < samples; ++s) {
    const float u1 = rng.next_float(), u2 = rng.next_float();
    const glm::dvec3 d(frame.to_world(HemisphereCells::local_direction(u1, u2)));
    const float r = square.hit(x, d);
    cells.add(u1, u2, std::isfinite(r) ? colour : glm::vec3(0.0f), r);
  }
  return cells.estimate(frame);
}

// Cases: the point under the square's edge (the strongest translation gradient) and off to
// the side, the normal up and tilted.
struct GradientCase {
  glm::dvec3 x, n;
};

TEST(IrradianceGradients, MatchLambertsFormulaAboutASquare) {
  const Square square;
  const double h = 1e-4;
  for (const GradientCase& test :
       {GradientCase{{0.3, 0.2, 0.0}, {0.0, 0.0, 1.0}},
        GradientCase{{0.6, -0.1, 0.0}, glm::normalize(glm::dvec3(0.2, -0.1, 1.0))},
        GradientCase{{-0.9, 0.4, 0.2}, glm::normalize(glm::dvec3(-0.3, 0.0, 1.0))}}) {
    const IrradianceGather g = gather(square, test.x, test.n, 1 << 20);
    const double truth = square.irradiance_over_pi(test.x, test.n);
    // 2^20 samples of a 0/1 radiance: the value is within 0.1% of the truth (its standard
    // error, sqrt(p (1 - p) / n) / p, is under 0.15% for p >= 0.05).
    EXPECT_NEAR(g.value.x, truth, 0.005 * truth);
    EXPECT_NEAR(g.value.y, 0.5 * truth, 0.005 * truth);

    const Frame frame{glm::vec3(test.n)};
    const std::array<glm::dvec3, 2> tangents{glm::dvec3(frame.tangent),
                                             glm::dvec3(frame.bitangent)};
    // Central differences of the closed form: moving x along the tangents, and turning n
    // about them.
    std::array<double, 2> translation{}, rotation{};
    for (int i = 0; i < 2; ++i) {
      const glm::dvec3 t = tangents[size_t(i)];
      translation[size_t(i)] = (square.irradiance_over_pi(test.x + h * t, test.n) -
                                square.irradiance_over_pi(test.x - h * t, test.n)) /
                               (2.0 * h);
      const auto turned = [&](double angle) {
        return glm::normalize(test.n + angle * glm::cross(t, test.n));
      };
      rotation[size_t(i)] = (square.irradiance_over_pi(test.x, turned(h)) -
                             square.irradiance_over_pi(test.x, turned(-h))) /
                            (2.0 * h);
    }
    const double translation_norm = std::hypot(translation[0], translation[1]);
    const double rotation_norm = std::hypot(rotation[0], rotation[1]);
    for (int i = 0; i < 2; ++i) {
      const glm::dvec3 t = tangents[size_t(i)];
      // The cells are 1/8 of sin² θ by 1/32 of the azimuth and the square's edges cross
      // them, so the formula sees each edge smeared over a cell: measured 5.4% of the
      // gradient at most (the paper's azimuthal term instead: 15-52% off, so this fails
      // it). Rotation needs no boundaries: measured 3.4% at most. The samples' own noise is
      // under 0.5% of either.
      EXPECT_NEAR(glm::dot(glm::dvec3(g.translational[0]), t), translation[size_t(i)],
                  0.08 * translation_norm);
      EXPECT_NEAR(glm::dot(glm::dvec3(g.rotational[0]), t), rotation[size_t(i)],
                  0.05 * rotation_norm);
      // The other channels are the same light at half and a quarter: the same gradients
      // scaled.
      EXPECT_NEAR(glm::dot(glm::dvec3(g.translational[2]), t),
                  0.25 * glm::dot(glm::dvec3(g.translational[0]), t), 1e-3 * translation_norm);
    }
    // The gradients lie in the tangent plane.
    EXPECT_NEAR(glm::dot(glm::dvec3(g.translational[0]), test.n), 0.0, 1e-5);
    EXPECT_NEAR(glm::dot(glm::dvec3(g.rotational[0]), test.n), 0.0, 1e-5);
  }
}

}  // namespace
}  // namespace bakegi
