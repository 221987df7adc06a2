// Area light: a one-sided Lambertian emitter of radiance L (W/(m^2 sr)) that emits only
// towards `direction` (the light's -Z). Square and rectangle have side lengths, disk and
// ellipse diameters, size_x along axis_u and size_y along direction x axis_u. As in Cycles,
// squares and rectangles are sampled uniformly in solid angle (spherical_rectangle.h),
// disks and ellipses uniformly by area (the density converted to solid angle).
//
// Spread (Cycles' soft-box grid, Blender D10594): with a spread of full angle 2h below pi the
// radiance towards an angle a off the normal is L f(a), f(a) = max(tan h - tan a, 0) N with
// N = 1 / (tan h - h), which keeps the light's power (the integral of f cos over the
// hemisphere is pi, as a Lambertian emitter's); Cycles' area_light_spread_attenuation.
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
  // Spread: tan h and N above; N = 0 for a Lambertian emitter (spread 0 or pi).
  float tan_half_spread_ = 0.0f;
  float normalize_spread_ = 0.0f;
  // f(a) of the spread for the cosine of a (1 without spread).
  float spread_attenuation(float cos_light) const;
  SphericalRectangle::Shape rectangle_;  // squares and rectangles: the frame sampling uses
};

}  // namespace bakegi
