#include "scene/passing_surfaces.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "scene/fresnel.h"
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
  for (const Material& m : materials_) {
    fresnel_averages_.push_back(
        m.transmission_ior > 0.0f ? fresnel_hemispherical_average(m.transmission_ior) : 0.0f);
  }
  for (size_t t = 0; t < scene.triangles.size(); ++t) {
    if (!scene.material_of(scene.triangles[t]).lets_light_pass()) continue;
    indices_.push_back(uint32_t(t));
    triangles_.push_back(scene.triangles[t]);
  }
}

bool PassingSurfaces::passes(uint32_t index, float b1, float b2, uint32_t seed,
                             const glm::vec3& origin, const glm::vec3& direction) const {
  const Triangle& t = triangles_[index];
  const Material& material = materials_[t.material];
  float transmission = material.transmission;
  if (material.transmission_ior > 0.0f) {
    // Glass: the share passing at this angle, transmission x (1 - F) / (1 - F_avg).
    const float cosine = std::abs(glm::dot(direction, t.face_normal)) / glm::length(direction);
    const float reflected = fresnel_dielectric(cosine, material.transmission_ior);
    const float average = fresnel_averages_[t.material];
    transmission =
        std::clamp(transmission * (1.0f - reflected) / std::max(1.0f - average, 1e-6f), 0.0f, 1.0f);
  }
  const float present = presence_at(material, textures_, t, b1, b2);
  const float probability = 1.0f - present * (1.0f - transmission);
  if (probability <= 0.0f) return false;
  if (probability >= 1.0f) return true;
  return pass_number(index, seed, origin, direction) < probability;
}

}  // namespace bakegi
