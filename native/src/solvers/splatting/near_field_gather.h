// Bias compensation for the bake (Kollig & Keller 2004, "Illumination in the presence of weak
// singularities"): the VPLs' light is exact far away and wrong near the surfaces they sit on,
// where the 1/r^2 of a point light stands for a patch. Here the VPLs send only
// min(G, b) of the geometry term G = cos cos / r^2, and a few cosine-weighted rays from the
// receiver add the rest, (1 - b / G)+ of the light reflected where they land (that point's
// direct light times its albedo / pi): together an unbiased one-bounce estimate whose rays
// matter only near corners and contacts. The bound b = 1 / d^2 with d a few radii of a
// VPL's surface. The rays see occluders, so the near field also gets its visibility.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "solvers/splatting/virtual_point_lights.h"

namespace bakegi {

struct Scene;
class RayTracer;
class DirectLight;

// b for VPLs: 1 / d^2 with d = `radii` times the radius of a disk of the VPLs' mean area.
float geometry_bound(const VirtualPointLights& vpls, float radii);

// The VPLs [begin, end) with G clamped to `bound`, irradiance / pi (no visibility).
glm::vec3 clamped_vpl_light(const VirtualPointLights& vpls, const glm::vec3& position,
                            const glm::vec3& normal, size_t begin, size_t end, float bound);

// What the clamp left out, irradiance / pi, from `rays` cosine-weighted rays (seeded by
// seed and point); the rays traced (gather and shadow rays) are added to `traced`.
glm::vec3 near_field_residual(const Scene& scene, const RayTracer& tracer,
                              const DirectLight& direct, const glm::vec3& position,
                              const glm::vec3& normal, float bound, uint32_t rays, uint64_t seed,
                              uint64_t point, uint64_t& traced);

}  // namespace bakegi
