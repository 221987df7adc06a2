// Uniform sampling of a rectangle's solid angle (lights/spherical_rectangle.h): the solid
// angle against the closed form, from close and oblique to a millimetre square ten metres
// away, and the samples' spread over the rectangle against each part's own solid angle.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "lights/spherical_rectangle.h"

namespace bakegi::test {
namespace {

// The solid angle of [0, x] x [0, y] in the plane z = -d, seen from the origin, signed by
// x y (Van Oosterom and Strackee's triangle formula on the two halves).
double corner_solid_angle(double x, double y, double d) {
  return std::atan2(x * y, d * std::sqrt(x * x + y * y + d * d));
}

// [x0, x1] x [y0, y1] in the plane z = -d by inclusion and exclusion of corner rectangles.
double rectangle_solid_angle(double x0, double x1, double y0, double y1, double d) {
  return corner_solid_angle(x1, y1, d) - corner_solid_angle(x0, y1, d) -
         corner_solid_angle(x1, y0, d) + corner_solid_angle(x0, y0, d);
}

SphericalRectangle::Shape shape(double x0, double x1, double y0, double y1, double d) {
  return SphericalRectangle::Shape(glm::dvec3(x0, y0, -d), glm::dvec3(x1 - x0, 0, 0),
                                   glm::dvec3(0, y1 - y0, 0));
}

struct Case {
  double x0, x1, y0, y1, d;
};

TEST(SphericalRectangle, SolidAngleMatchesTheClosedForm) {
  const Case cases[] = {
      {-1, 1, -1, 1, 1},           // centred, close
      {-0.5, 3, 0.2, 0.7, 0.05},   // oblique, nearly in the plane's reach
      {2, 5, -4, -1, 0.3},         // off to one side
      {-10, 10, -10, 10, 0.001},   // nearly a hemisphere
      {7, 7.001, 3, 3.002, 10.0},  // a 1 x 2 mm patch far off the axis: S ~ 1e-8 sr
  };
  for (const Case& c : cases) {
    const SphericalRectangle r(glm::dvec3(0.0), shape(c.x0, c.x1, c.y0, c.y1, c.d));
    const double expected = rectangle_solid_angle(c.x0, c.x1, c.y0, c.y1, c.d);
    // Both sides carry double rounding of angles near pi: about 1e-16 sr.
    EXPECT_NEAR(r.solid_angle(), expected, 1e-9 * expected + 1e-15)
        << c.x0 << " " << c.x1 << " " << c.y0 << " " << c.y1 << " " << c.d;
  }
  // Seen from behind (z > 0 side swapped), the same.
  const SphericalRectangle behind(glm::dvec3(0, 0, -2), shape(-1, 1, -1, 1, 1));
  EXPECT_NEAR(behind.solid_angle(), rectangle_solid_angle(-1, 1, -1, 1, 1), 1e-12);
}

TEST(SphericalRectangle, SamplesAreUniformInSolidAngle) {
  const Case cases[] = {{-0.5, 3, 0.2, 0.7, 0.3}, {-1, 1, -1, 1, 1}, {7, 7.01, 3, 3.02, 10.0}};
  constexpr int kCells = 4;
  constexpr int kSamples = 64000;
  for (const Case& c : cases) {
    const SphericalRectangle r(glm::dvec3(0.0), shape(c.x0, c.x1, c.y0, c.y1, c.d));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    int counts[kCells][kCells] = {};
    const double wx = (c.x1 - c.x0) / kCells, wy = (c.y1 - c.y0) / kCells;
    for (int s = 0; s < kSamples; ++s) {
      const glm::dvec3 q = r.sample(uniform(rng), uniform(rng));
      ASSERT_NEAR(q.z, -c.d, 1e-9 * c.d);
      const double tolerance = 1e-9 * (c.x1 - c.x0 + c.y1 - c.y0);
      ASSERT_GE(q.x, c.x0 - tolerance);
      ASSERT_LE(q.x, c.x1 + tolerance);
      ASSERT_GE(q.y, c.y0 - tolerance);
      ASSERT_LE(q.y, c.y1 + tolerance);
      const int i = std::clamp(int((q.x - c.x0) / wx), 0, kCells - 1);
      const int j = std::clamp(int((q.y - c.y0) / wy), 0, kCells - 1);
      ++counts[i][j];
    }
    for (int i = 0; i < kCells; ++i) {
      for (int j = 0; j < kCells; ++j) {
        const double share = rectangle_solid_angle(c.x0 + i * wx, c.x0 + (i + 1) * wx,
                                                   c.y0 + j * wy, c.y0 + (j + 1) * wy, c.d) /
                             r.solid_angle();
        // Binomial spread of the count; 5 sigma over the 48 cells of the three cases.
        const double sigma = std::sqrt(kSamples * share * (1.0 - share));
        EXPECT_NEAR(counts[i][j], kSamples * share, 5.0 * sigma + 1.0)
            << "cell " << i << "," << j << " of case d=" << c.d;
      }
    }
  }
}

}  // namespace
}  // namespace bakegi::test
