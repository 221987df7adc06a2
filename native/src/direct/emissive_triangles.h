// Mesh emitters: every triangle whose material has emission, radiance Le, two-sided when
// the material says so (Cycles 3.4 mesh emission) and otherwise emitting only on the side
// of the face normal. Light sampling picks one triangle with probability proportional to
// area x emission (summed over RGB), then a uniform point on it.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "direct/light_sample.h"
#include "scene/scene.h"

namespace bakegi {

class EmissiveTriangles {
 public:
  explicit EmissiveTriangles(const Scene& scene);

  bool empty() const { return cdf_.empty(); }
  // Samples a point on an emitter as seen from p; false if it sends nothing there.
  bool sample(const glm::vec3& p, float u_pick, float u1, float u2, LightSample& out) const;
  // Radiance that triangle `triangle` emits along `direction` (the ray travelling towards
  // it), zero on the dark side of a one-sided emitter.
  glm::vec3 emitted(uint32_t triangle, const glm::vec3& direction) const;
  // Solid-angle density of sample() for the direction that hits `triangle` at distance t
  // with cosine cos_light (absolute) to its normal.
  float pdf(uint32_t triangle, float distance, float cos_light) const;

 private:
  const Scene& scene_;
  std::vector<uint32_t> triangles_;        // the emitters, in scene order
  std::vector<double> cdf_;                // normalized, cdf_.back() == 1
  std::vector<float> pick_pdf_over_area_;  // per scene triangle, 0 if not an emitter
};

}  // namespace bakegi
