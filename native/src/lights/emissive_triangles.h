// Mesh emitters: every triangle whose material has emission, radiance Le (times the
// material's emission texture at the point, where it has one), two-sided when the material
// says so (Cycles 3.4 mesh emission) and otherwise emitting only on the side of the face
// normal. Light sampling picks one cell of one triangle (Scene::emission_cells: the whole
// triangle for an untextured emitter, a few texels' worth of a textured one) with
// probability proportional to area x mean emission (summed over RGB), then a uniform point in
// it. pdf() gives the density of exactly that choice at any point, so the BSDF-sampled half
// of MIS (DirectLight::emission_along) weighs every hit consistently, black cells (never
// picked) included.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "lights/light_sample.h"
#include "scene/scene.h"

namespace bakegi {

class EmissiveTriangles {
 public:
  explicit EmissiveTriangles(const Scene& scene);

  bool empty() const { return cdf_.empty(); }
  // Samples a point on an emitter as seen from p; false if it sends nothing there.
  bool sample(const glm::vec3& p, float u_pick, float u1, float u2, LightSample& out) const;
  // Radiance that triangle `triangle` emits at barycentrics (b1, b2) along `direction` (the
  // ray travelling towards it), zero on the dark side of a one-sided emitter.
  glm::vec3 emitted(uint32_t triangle, float b1, float b2, const glm::vec3& direction) const;
  // Solid-angle density of sample() for the direction that hits `triangle` at barycentrics
  // (b1, b2), distance t, with cosine cos_light (absolute) to its normal.
  float pdf(uint32_t triangle, float b1, float b2, float distance, float cos_light) const;

 private:
  struct Emitter {
    uint32_t triangle;  // index into Scene::triangles
    uint32_t level;     // its cells (scene/triangle_cells.h)
    uint64_t first_cell;
  };
  static constexpr uint32_t kNotSampled = 0xFFFFFFFFu;

  const Scene& scene_;
  std::vector<Emitter> emitters_;              // those with power, in scene order
  std::vector<double> cdf_;                    // over their cells, normalized, back() == 1
  std::vector<float> cell_pdf_over_area_;      // probability of a cell / its area
  std::vector<uint32_t> emitter_of_triangle_;  // per scene triangle: into emitters_ or kNotSampled
};

}  // namespace bakegi
