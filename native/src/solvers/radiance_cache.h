// A solver's solution read where a ray lands: the irradiance a surface receives, split into
// direct and indirect, as a cheap and smooth estimate of the light it reflects. The
// path-traced residual (solvers/pathtrace/controlled_path.h) uses it as a control variate,
// antiradiance's near-field gather as the light beyond the first bounce.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "scene/ray_tracer.h"

namespace bakegi {

// Irradiance over pi (the output convention): multiplied by the albedo at the hit it is the
// radiance a diffuse surface reflects.
struct CachedIrradiance {
  glm::vec3 direct_over_pi{0.0f};
  glm::vec3 indirect_over_pi{0.0f};
};

class RadianceCache {
 public:
  virtual ~RadianceCache() = default;
  // The cached irradiance at the surface `hit` of a ray travelling along `direction`, on the
  // side the ray arrives from; false where the cache has no value (then `out` is unchanged).
  virtual bool irradiance_at(const Hit& hit, const glm::vec3& direction,
                             CachedIrradiance& out) const = 0;
  virtual size_t memory_bytes() const = 0;
};

}  // namespace bakegi
