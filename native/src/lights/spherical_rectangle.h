// Uniform sampling of the solid angle a rectangle subtends at a point (Urena, Fajardo and
// King 2013, "An Area-Preserving Parametrization for Spherical Rectangles"), the strategy
// Cycles uses for rectangular area lights: every sample has density 1 / S, so a nearby
// large light is sampled without the 1/d^2 spread of uniform area sampling. Computed in
// double: S comes from a difference of angles near 2 pi, which float would lose for small
// or distant rectangles.
#pragma once

#include <glm/glm.hpp>

namespace bakegi {

class SphericalRectangle {
 public:
  // The part that does not depend on the viewing point, computed once per light: the
  // rectangle corner + s * edge_u + t * edge_v (s, t in [0,1], edges orthogonal).
  struct Shape {
    Shape() = default;
    Shape(const glm::dvec3& corner, const glm::dvec3& edge_u, const glm::dvec3& edge_v);

    glm::dvec3 corner{0.0};
    glm::dvec3 x{0.0}, y{0.0}, z{0.0};  // unit edge directions and x cross y
    double length_u = 0.0, length_v = 0.0;
  };

  // `shape` seen from `point`.
  SphericalRectangle(const glm::dvec3& point, const Shape& shape);

  double solid_angle() const { return solid_angle_; }
  // A point on the rectangle, uniform in solid angle for (u1, u2) uniform in [0,1)^2.
  glm::dvec3 sample(double u1, double u2) const;

 private:
  glm::dvec3 point_;
  glm::dvec3 x_, y_, z_;  // local frame: x, y along the edges, z towards the rectangle
  double x0_, x1_, y0_, y1_, z0_;
  double b0_, b1_, k_;
  double solid_angle_ = 0.0;
};

}  // namespace bakegi
