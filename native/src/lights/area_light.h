// Area light: a one-sided Lambertian emitter of radiance L (W/(m^2 sr)) that emits only
// towards `direction` (the light's -Z). Square and rectangle have side lengths, disk and
// ellipse diameters, size_x along axis_u and size_y along direction x axis_u. As in Cycles,
// squares and rectangles are sampled uniformly in solid angle (spherical_rectangle.h),
// disks and ellipses uniformly by area (the density converted to solid angle).
#pragma once

#include <glm/glm.hpp>

#include "lights/light_sample.h"
#include "lights/spherical_rectangle.h"
#include "scene/scene.h"

namespace bakegi {

class AreaLight {
 public:
  explicit AreaLight(const Light& light);
  // False for a light with Cast Shadow off (BAKEGI_LIGHT_NO_SHADOW).
  bool casts_shadow() const { return casts_shadow_; }

  bool sample(const glm::vec3& p, float u1, float u2, LightSample& out) const;
  bool intersect(const glm::vec3& origin, const glm::vec3& direction, float t_max,
                 LightHit& out) const;
  float area() const { return area_; }
  const glm::vec3& radiance() const { return radiance_; }
  const glm::vec3& normal() const { return normal_; }  // the emitting side
  const glm::vec3& center() const { return center_; }
  // The point of the light's shape at (u1, u2) in [0,1)^2, uniform by area (reflective
  // shadow maps place their views there).
  glm::vec3 point_at(float u1, float u2) const;

 private:
  SphericalRectangle spherical_rectangle(const glm::vec3& p) const {
    return SphericalRectangle(glm::dvec3(p), rectangle_);
  }

  bool casts_shadow_;
  glm::vec3 center_;
  glm::vec3 normal_;  // emission side
  glm::vec3 axis_u_, axis_v_;
  float half_u_, half_v_;
  bool round_;
  float area_;
  glm::vec3 radiance_;
  SphericalRectangle::Shape rectangle_;  // squares and rectangles: the frame sampling uses
};

}  // namespace bakegi
