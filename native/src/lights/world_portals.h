// Window portals (Cycles' area lights with Portal on): shapes placed in a room's windows that
// emit nothing but say where the world's light comes in. From a point on a portal's inner
// side (the side its `direction` faces), a direction through the portal, uniform in the
// solid angle the portal subtends there (squares and rectangles; disks and ellipses uniform
// by area, as their area lights are sampled), goes on to the sky: the world's light sample
// aims there instead of over the whole sphere, most of which a room's walls hide.
//
// The density of a direction is the mean over the portals of the density of each one it
// crosses (one portal is chosen uniformly), so overlapping portals stay unbiased.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "lights/area_light.h"
#include "scene/scene.h"

namespace bakegi {

class WorldPortals {
 public:
  explicit WorldPortals(const std::vector<Light>& portals);

  bool empty() const { return shapes_.empty(); }
  size_t size() const { return shapes_.size(); }
  // Whether x is on the inner side of at least one portal, off its plane by more than 1e-4
  // of its size (where the caller should use sample() and pdf()).
  bool seen_from(const glm::vec3& x) const;
  // A unit direction from x through a portal chosen by u0 (uniform), its point by (u1, u2);
  // `pdf` is pdf(x, direction). False when the chosen portal cannot be seen from x.
  bool sample(const glm::vec3& x, float u0, float u1, float u2, glm::vec3& direction,
              float& pdf) const;
  // Solid-angle density of sample() at x for the unit direction.
  float pdf(const glm::vec3& x, const glm::vec3& direction) const;

 private:
  std::vector<AreaLight> shapes_;     // emitting nothing: only their geometry and sampling are used
  std::vector<float> seen_distance_;  // per portal: how far off its plane a point sees it
};

}  // namespace bakegi
