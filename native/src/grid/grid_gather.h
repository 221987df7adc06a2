// Gathering the Irradiance Vector Grid (Pacanowski et al. 2008, §3.1, Eq. 1): at every grid
// vertex and for each of its six hemispheres, `rays_per_hemisphere` directions uniform over
// the hemisphere (Owen-scrambled Sobol' points, so each hemisphere's rays are stratified) are
// traced with Embree; the radiance L each first hit reflects back (grid_hit_radiance.h) gives
//   I_delta = integral of L(w) w dw  ~  2 pi / N * sum of L_i w_i   (density 1 / (2 pi)).
// Uniform rather than cosine-weighted: I's components along the hemisphere's sides weigh w
// by sin, which a cosine density would divide by cos (unbounded variance at grazing rays).
//
// A vertex inside geometry (inside a closed object, behind a wall) sees back faces: when at
// least backface_fraction of its rays hit one, it is marked invalid, like the lightmap
// texels of lightmap/backface_rejection.h, and push-pull (grid_push_pull.h) fills it.
//
// The same rays give, for free, the light that arrives straight from the world (rays that
// escape) and from emissive surfaces (rays that meet their emitting side): the grid's
// `emitted` component, gathered when the scene has a world or an emitter. It is direct light
// for a receiver, so bakes leave it out; the web page adds it to the grid it streams.
#pragma once

#include <cstdint>

#include "grid/irradiance_vector_grid.h"

namespace bakegi {

class HitRadiance;
class JobContext;
class RayTracer;
struct Scene;

struct GridGatherOptions {
  uint32_t rays_per_hemisphere = 64;  // 1..65536
  uint64_t seed = 0;
  // A vertex whose rays hit back faces this often or more is inside geometry, (0, 1].
  float backface_fraction = 0.25f;
  // Rays start this far from the vertex (a vertex may lie on a surface).
  float ray_epsilon = 0.0f;
};

struct GridGatherStatistics {
  uint64_t rays = 0;  // every ray traced: the grid's own and the hit radiance's
  uint64_t invalid_vertices = 0;
};

// Whether gather_grid gathers the emitted light: the scene has a world or an emitter.
bool grid_gathers_emitted(const Scene& scene);

// Reports progress over the current stage; throws Error(CANCELLED) when cancelled and
// Error(INVALID_ARGUMENT) for options out of range.
IrradianceVectorGrid gather_grid(const GridLayout& layout, const Scene& scene,
                                 const RayTracer& tracer, const HitRadiance& radiance,
                                 const GridGatherOptions& options, JobContext& context,
                                 GridGatherStatistics& statistics);

}  // namespace bakegi
