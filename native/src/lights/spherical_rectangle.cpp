#include "lights/spherical_rectangle.h"

#include <algorithm>
#include <cmath>

namespace bakegi {

namespace {

double safe_acos(double x) {
  return std::acos(std::clamp(x, -1.0, 1.0));
}

}  // namespace

SphericalRectangle::Shape::Shape(const glm::dvec3& corner, const glm::dvec3& edge_u,
                                 const glm::dvec3& edge_v)
    : corner(corner), length_u(glm::length(edge_u)), length_v(glm::length(edge_v)) {
  x = edge_u / length_u;
  y = edge_v / length_v;
  z = glm::cross(x, y);
}

SphericalRectangle::SphericalRectangle(const glm::dvec3& point, const Shape& shape)
    : point_(point), x_(shape.x), y_(shape.y), z_(shape.z) {
  const double length_u = shape.length_u, length_v = shape.length_v;
  const glm::dvec3 d = shape.corner - point;
  z0_ = glm::dot(d, z_);
  if (z0_ > 0.0) {  // the local z must point away from the rectangle's plane
    z_ = -z_;
    z0_ = -z0_;
  }
  x0_ = glm::dot(d, x_);
  y0_ = glm::dot(d, y_);
  x1_ = x0_ + length_u;
  y1_ = y0_ + length_v;
  // z components of the normals of the four planes through the point and an edge; the
  // internal angles of the spherical rectangle follow from them.
  const double dx = x1_ - x0_, dy = y1_ - y0_;
  auto normal_z = [&](double along, double diff) {
    const double n = along * diff;
    return n / std::sqrt(z0_ * z0_ * diff * diff + n * n);
  };
  const double n0 = normal_z(y0_, -dx), n1 = normal_z(x1_, dy), n2 = normal_z(y1_, dx),
               n3 = normal_z(x0_, -dy);
  const double g0 = safe_acos(-n0 * n1), g1 = safe_acos(-n1 * n2), g2 = safe_acos(-n2 * n3),
               g3 = safe_acos(-n3 * n0);
  b0_ = n0;
  b1_ = n2;
  k_ = 2.0 * M_PI - g2 - g3;
  solid_angle_ = std::max(0.0, g0 + g1 - k_);
}

glm::dvec3 SphericalRectangle::sample(double u1, double u2) const {
  // Invert the solid angle along x, then along y at that x.
  const double au = u1 * solid_angle_ + k_;
  const double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
  double cu = std::copysign(1.0, fu) / std::sqrt(fu * fu + b0_ * b0_);
  cu = std::clamp(cu, -1.0, 1.0);
  double xu = -(cu * z0_) / std::max(std::sqrt(1.0 - cu * cu), 1e-12);
  xu = std::clamp(xu, x0_, x1_);
  const double dist = std::sqrt(xu * xu + z0_ * z0_);
  const double h0 = y0_ / std::sqrt(dist * dist + y0_ * y0_);
  const double h1 = y1_ / std::sqrt(dist * dist + y1_ * y1_);
  const double hv = h0 + u2 * (h1 - h0);
  const double hv2 = hv * hv;
  const double yv = hv2 < 1.0 - 1e-12 ? hv * dist / std::sqrt(1.0 - hv2) : y1_;
  return point_ + x_ * xu + y_ * std::clamp(yv, y0_, y1_) + z_ * z0_;
}

}  // namespace bakegi
