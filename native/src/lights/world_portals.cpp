#include "lights/world_portals.h"

#include <algorithm>
#include <limits>

namespace bakegi {

WorldPortals::WorldPortals(const std::vector<Light>& portals) {
  shapes_.reserve(portals.size());
  for (Light portal : portals) {
    portal.spot_size = 0.0f;  // no spread: every direction through it is sampled alike
    shapes_.emplace_back(portal);
    // A point in the portal's plane (the wall around a window) sees it edge-on: a solid
    // angle of 0, and float rounding would put it on either side.
    seen_distance_.push_back(1e-4f * std::max(portal.size_x, portal.size_y));
  }
}

bool WorldPortals::seen_from(const glm::vec3& x) const {
  for (size_t i = 0; i < shapes_.size(); ++i) {
    if (glm::dot(x - shapes_[i].center(), shapes_[i].normal()) > seen_distance_[i]) return true;
  }
  return false;
}

bool WorldPortals::sample(const glm::vec3& x, float u0, float u1, float u2, glm::vec3& direction,
                          float& pdf_out) const {
  if (shapes_.empty()) return false;
  const size_t chosen = std::min(size_t(u0 * float(shapes_.size())), shapes_.size() - 1);
  LightSample s;
  if (!shapes_[chosen].sample(x, u1, u2, s)) return false;
  direction = s.direction;
  if (shapes_.size() == 1) {
    pdf_out = s.pdf;
  } else {
    pdf_out = pdf(x, direction);
  }
  return pdf_out > 0.0f;
}

float WorldPortals::pdf(const glm::vec3& x, const glm::vec3& direction) const {
  if (shapes_.empty()) return 0.0f;
  float sum = 0.0f;
  LightHit hit;
  for (const AreaLight& shape : shapes_) {
    if (shape.intersect(x, direction, std::numeric_limits<float>::infinity(), hit)) {
      sum += hit.pdf;
    }
  }
  return sum / float(shapes_.size());
}

}  // namespace bakegi
