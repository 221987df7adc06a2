// Output near other surfaces: a final gather from the antiradiance solution.
//
// The weighted splat (surface_interpolation.h) reads a smooth function off patch centres; it
// cannot follow irradiance that changes within one patch of a bake point. That happens where
// another surface is near: along concave edges and contact lines the nearby surface fills
// much of the hemisphere, and on the Cornell box the room's edges (10% of the face corners)
// held 58% of the squared error at 192 bins, biased +13%. There the bake point gathers
// instead, as radiosity renderers do:
//
//   E(x) / π = 1/π ∫ L_out(y) cos θ dω ≈ mean over cosine-distributed rays of L_out(y),
//   L_out(y) = ρ(y) (E_direct(y) + E_indirect(y)) / π,
//
// with ρ the albedo at the hit, E_direct one sample of the direct-light module at the hit
// (exact shadows: a patch that straddles a contact line has one value for both sides, and a
// box's base gathers mostly from such floor patches) and E_indirect that of the patch the ray
// lands on (patch_locator.h: piecewise constant, but never blurred across an edge; the back
// of a solid's face has no patch and reflects nothing). Emission, lamps and the world are
// direct light and stay out.
//
// A fixed pattern of kProbeSide² probe rays first looks for a surface closer than `far` (most
// points have none and keep the splat); the gather's own rays then measure the distance d to
// the nearest surface: at d ≥ `far` the splat is used, at d ≤ `near` the gather, in between a
// smooth blend, so no seam appears where the method switches. A point whose rays mostly hit
// the backs of faces (inside or behind geometry) keeps the splat.
#pragma once

#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "solvers/antiradiance/patch_radiance_cache.h"

namespace bakegi {
struct Scene;
class RayTracer;
class DirectLight;
}  // namespace bakegi

namespace bakegi::antiradiance {

struct NearFieldSettings {
  uint32_t rays = 0;  // per bake point; 0 disables the gather
  float near = 0.0f;  // below this distance to another surface: the gather alone
  float far = 0.0f;   // beyond it: the splat alone
  float ray_epsilon = 1e-4f;
  uint64_t seed = 0;
};

class NearFieldGather {
 public:
  static constexpr uint32_t kProbeSide = 4;

  NearFieldGather() = default;
  // `direct` (and its scene and tracer) must outlive every evaluate(). The gather reads
  // E_indirect / π of the patch each ray lands on from `cache` (its direct part is not used:
  // the gather samples direct light at the hit with exact shadows).
  NearFieldGather(const DirectLight& direct, std::shared_ptr<const PatchRadianceCache> cache,
                  const NearFieldSettings& settings);

  bool enabled() const { return direct_ != nullptr && settings_.rays > 0; }
  // Blends the gathered value into `splat` (the splat's value at this point) by the distance
  // to the nearest surface the rays found; `point` keys the random stream. Adds its rays
  // (gather and shadow) to `rays`.
  glm::vec3 evaluate(const glm::vec3& position, const glm::vec3& normal, uint64_t point,
                     const glm::vec3& splat, uint64_t& rays) const;
  // For a point off every surface (SurfaceInterpolation's off_surface): the gather alone,
  // every ray counting (a ray that misses or meets the back of a face brings no indirect
  // light). False when the gather is disabled.
  bool gather_off_surface(const glm::vec3& position, const glm::vec3& normal, uint64_t point,
                          glm::vec3& value, uint64_t& rays) const;
  const NearFieldSettings& settings() const { return settings_; }
  // The cache is shared with the field's other users and counted by its owner.

 private:
  struct Gathered {
    glm::dvec3 sum{0.0};
    float nearest = 0.0f;
    uint32_t unseen = 0;
  };
  Gathered gather(const glm::vec3& position, const glm::vec3& normal, uint64_t point,
                  uint64_t& rays_cast) const;

  const DirectLight* direct_ = nullptr;
  std::shared_ptr<const PatchRadianceCache> cache_;
  NearFieldSettings settings_;
};

}  // namespace bakegi::antiradiance
