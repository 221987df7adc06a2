// Reflective shadow maps (Nichols & Wyman 2009, §2.1 and §3.1; Dachsbacher & Stamminger
// 2005): for each light, the surfaces it sees first, one texel per ray, each texel storing
// world position, the normal facing the light, albedo and the flux it reflects.
//
// The maps are traced with Embree rather than rasterized, one view per light kind:
//   spot                one perspective map over the cone,
//   point               a cube of six perspective maps,
//   sun                 one orthographic map over the scene's bounds,
//   area light, emissive meshes   "sets of spots": points on the emitter, each a cosine-
//                       weighted hemisphere map (equal emitted power per texel),
//   world               orthographic maps from a set of directions over the sphere.
// A texel's flux is the power its ray carries (exact for the emitter's own units: intensity
// times solid angle, radiance times projected area and solid angle, irradiance times area)
// times the albedo where it lands; its area is the surface the ray stands for (what the
// flux is spread over), which later bounds the VPL's 1/r^2 near field.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

struct Scene;
class RayTracer;

struct RsmTexel {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // shading normal, on the side facing the light
  glm::vec3 albedo{0.0f};
  glm::vec3 flux{0.0f};  // reflected flux, W (zero: the ray missed or hit black)
  float area = 0.0f;     // m^2 of surface the texel stands for
};

// One view of one light: width x height texels in row order.
struct ReflectiveShadowMap {
  uint32_t light = 0;  // index into the scene's lights; lights().size() for emissive meshes,
                       // lights().size() + 1 for the world
  std::string kind;    // "spot", "point face", "sun", "area spot", "emissive spot", "world"
  uint32_t width = 0, height = 0;
  std::vector<RsmTexel> texels;
};

struct RsmOptions {
  uint32_t resolution = 128;  // texels per side of a light's maps taken together
  uint32_t spots = 16;        // views per area light, for emissive meshes and for the world
  float ray_epsilon = 1e-4f;  // offset of rays leaving emitter surfaces
};

// Every light's maps (lamps in scene order, then emissive meshes, then the world). Lights
// that send nothing (zero power, a spot pointing at nothing) give maps whose texels hold no
// flux. Runs on the calling thread's TBB arena.
std::vector<ReflectiveShadowMap> render_reflective_shadow_maps(const Scene& scene,
                                                               const RayTracer& tracer,
                                                               const RsmOptions& options);

// The sum of the reflected flux over all texels (W, RGB): what one bounce can send out.
glm::dvec3 total_reflected_flux(const std::vector<ReflectiveShadowMap>& maps);

}  // namespace bakegi
