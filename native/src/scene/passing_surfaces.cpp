#include "scene/passing_surfaces.h"

#include <cstring>

#include "util/pcg32.h"

namespace bakegi {

namespace {

uint64_t bits(float value) {
  uint32_t b;
  std::memcpy(&b, &value, sizeof b);
  return b;
}

// A uniform number in [0, 1) from everything that tells one ray's meeting with one triangle
// from another.
float pass_number(uint32_t index, uint32_t seed, const glm::vec3& o, const glm::vec3& d) {
  uint64_t h = mix64(uint64_t(index) << 32 | seed);
  h = mix64(h ^ (bits(o.x) << 32 | bits(o.y)));
  h = mix64(h ^ (bits(o.z) << 32 | bits(d.x)));
  h = mix64(h ^ (bits(d.y) << 32 | bits(d.z)));
  return float(h >> 40) * (1.0f / 16777216.0f);
}

}  // namespace

PassingSurfaces::PassingSurfaces(const Scene& scene)
    : materials_(scene.description.materials), textures_(scene.description.textures) {
  for (size_t t = 0; t < scene.triangles.size(); ++t) {
    if (!scene.material_of(scene.triangles[t]).lets_light_pass()) continue;
    indices_.push_back(uint32_t(t));
    triangles_.push_back(scene.triangles[t]);
  }
}

bool PassingSurfaces::passes(uint32_t index, float b1, float b2, uint32_t seed,
                             const glm::vec3& origin, const glm::vec3& direction) const {
  const Triangle& t = triangles_[index];
  const float probability = pass_probability_at(materials_[t.material], textures_, t, b1, b2);
  if (probability <= 0.0f) return false;
  if (probability >= 1.0f) return true;
  return pass_number(index, seed, origin, direction) < probability;
}

}  // namespace bakegi
