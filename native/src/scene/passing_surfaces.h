// See-through triangles (window glass, cut-out leaves): which rays pass them. The ray tracer
// puts these triangles in a geometry of their own whose Embree filter asks decide(); the
// opaque rest is traced without a filter, so scenes without such surfaces cost nothing more.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace bakegi {

class PassingSurfaces {
 public:
  // The triangles of `scene` whose material lets light pass (Material::lets_light_pass).
  explicit PassingSurfaces(const Scene& scene);

  bool empty() const { return triangles_.empty(); }
  // Scene::triangles indices of the passing triangles, in the order they were found.
  const std::vector<uint32_t>& triangle_indices() const { return indices_; }

  // Whether a ray with this seed, origin and direction passes passing triangle `index` at
  // barycentrics (b1, b2): true with the material's pass probability there. A hash of all of
  // them, not a random draw: Embree may report one hit more than once, and every report must
  // get the same answer; the seed keeps rays that share origin and direction (a sun's shadow
  // rays from one bake point) from sharing their answers.
  bool passes(uint32_t index, float b1, float b2, uint32_t seed, const glm::vec3& origin,
              const glm::vec3& direction) const;

 private:
  std::vector<uint32_t> indices_;
  std::vector<Triangle> triangles_;  // copies: the tracer may outlive the scene it was built on
  std::vector<Material> materials_;
  std::vector<float> fresnel_averages_;  // per material, where it has a transmission IOR
  std::vector<Texture> textures_;        // share their texels with the scene's
};

}  // namespace bakegi
