// One sample of the indirect light at a bake point, in the output convention E_indirect/pi.
//
// From the point p (normal n) a cosine-weighted direction is traced to the first hit x1.
// With density cos/pi the sample of E/pi = integral of L cos/pi is simply the radiance
// arriving from x1, of which only the part x1 reflects counts: emission at x1, lamps
// crossed on the way and the world on a miss are direct light at p and excluded. At x1
// and every later vertex x_k (diffuse, two-sided, albedo rho_k):
//   reflected radiance = rho_k / pi * E(x_k),
//   E(x_k) = next-event estimate (MIS-weighted) + pi * L along a cosine-sampled ray
//            (emission found by that ray MIS-weighted, then the next vertex's reflection),
// so the path throughput is multiplied by rho_k per bounce. A vertex whose material has a
// glossy lobe uses the same two strategies with the diffuse + Phong mixture of
// scene/surface_bsdf.h (f cos in the light samples, the mixture's density in MIS, f cos / pdf
// in the throughput); diffuse vertices keep the path above exactly, random numbers included.
// Russian roulette after a few bounces keeps it unbiased; max_bounces caps the number of reflecting
// vertices (the last one still traces its BSDF ray so that emission MIS stays consistent).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "lights/surface_point.h"

namespace bakegi {

class DirectLight;
class RandomStream;

glm::vec3 sample_indirect(const DirectLight& direct, const SurfacePoint& point, RandomStream& rng,
                          int max_bounces, uint64_t& rays);

}  // namespace bakegi
