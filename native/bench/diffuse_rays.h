// Incoherent rays like a path tracer's: origins uniform over the scene's surface area,
// directions cosine-distributed about the face normal (bounces), or segments between
// surface points (shadow rays). Deterministic.
#pragma once

#include <vector>

#include "scene/ray_tracer.h"
#include "scene/scene.h"

namespace bakegi::bench {

std::vector<Ray> diffuse_bounce_rays(const Scene& scene, size_t count, uint64_t seed = 1);

// Shadow-ray-like segments between two random surface points (area-weighted), ending just
// short of the second: occlusion queries as incoherent as next-event estimation's.
std::vector<Ray> surface_to_surface_segments(const Scene& scene, size_t count, uint64_t seed = 2);

}  // namespace bakegi::bench
