// The world's direct light at the sender points, integrated from geometry once. The world is
// one colour from every direction, so its direct irradiance at a point is exactly
// π L_world V, with V the cosine-weighted fraction of the hemisphere that sees no geometry.
// V depends on geometry alone: the precomputation stores it and every lighting (any world
// colour) multiplies. Sampling the world with the one cosine ray of each direct-light sample
// instead finds a small skylight too rarely: with 4 samples per sender the room of
// test_solver_light_types.cpp came out 18% bright on its floor (too few senders to average
// the spread away, and P† weights them unevenly).
#pragma once

#include <cstdint>
#include <vector>

#include "solvers/meshless/basis_hierarchy.h"

namespace bakegi {
class JobContext;
class RayTracer;
}  // namespace bakegi

namespace bakegi::meshless {

struct SkyVisibilitySettings {
  uint32_t rays = 64;  // per point, jittered strata of the cosine-weighted hemisphere
  float ray_epsilon = 1e-4f;
  uint64_t seed = 0;
};

// V per point of `points` (in [0, 1]); counts the rays cast into `rays_cast`. Cancellable.
std::vector<float> sky_visibility(const BasisHierarchy& points, const RayTracer& tracer,
                                  const SkyVisibilitySettings& settings, JobContext& context,
                                  uint64_t& rays_cast);

}  // namespace bakegi::meshless
