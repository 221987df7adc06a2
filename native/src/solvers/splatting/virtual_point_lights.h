// Virtual point lights from reflective shadow maps (Nichols & Wyman 2009, §3.1) and the
// light one of them sends to a diffuse receiver (their equation 2 with diffuse BRDFs).
//
// Selection is either the paper's fixed regular grid over each map (one VPL per block of
// texels, at the block's centre texel, carrying the block's flux), or importance sampling
// of texels by reflected flux (systematic, so the count is exact). Either way the VPLs
// carry all the maps' flux: their sum is total_reflected_flux(maps).
//
// The 1/r^2 singularity the paper clamps (their Fig. 13) is bounded here by the surface a
// VPL stands for: it shines like a disk of that area, whose on-axis irradiance
// Phi / (pi (r^2 + A/pi)) stays finite as r -> 0 and tends to Phi / (pi r^2) far away.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/splatting/reflective_shadow_map.h"

namespace bakegi {

enum class VplSampling { kRegular, kImportance };

// Structure of arrays: the gather's inner loop runs over VPLs.
struct VirtualPointLights {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec3> fluxes;  // W, RGB (reflected, diffuse)
  std::vector<float> disk_areas;  // A / pi of each VPL's surface: the near-field bound
  // Regular sampling: the texels each VPL gathers, [texel_begin[v], texel_begin[v + 1]) of
  // `texels`, for receivers so close that the block's extent matters (near_field_light).
  std::vector<uint32_t> texel_begin;
  std::vector<RsmTexel> texels;
  size_t size() const { return positions.size(); }
  void push(const glm::vec3& position, const glm::vec3& normal, const glm::vec3& flux, float area);
};

VirtualPointLights select_vpls(const std::vector<ReflectiveShadowMap>& maps, uint32_t count,
                               VplSampling sampling);

// The indirect light the VPLs [begin, end) send to a receiver at `position` with unit
// `normal`, in the output convention: irradiance / pi, so that albedo x value is the diffuse
// radiance it reflects. No visibility: the paper's approximation.
glm::vec3 vpl_irradiance_over_pi(const VirtualPointLights& vpls, const glm::vec3& position,
                                 const glm::vec3& normal, size_t begin, size_t end);
inline glm::vec3 vpl_irradiance_over_pi(const VirtualPointLights& vpls, const glm::vec3& position,
                                        const glm::vec3& normal) {
  return vpl_irradiance_over_pi(vpls, position, normal, 0, vpls.size());
}

// As vpl_irradiance_over_pi, but a VPL closer than `split` times the radius of the surface it
// stands for sends its texels' light instead of its own (each bounded by its own area): the
// VPL's single point misplaces light near it (the bias the paper's Fig. 13 clamps away),
// which its texels resolve down to the maps' resolution. Without texels (importance sampling)
// this is vpl_irradiance_over_pi.
glm::vec3 near_field_light(const VirtualPointLights& vpls, const glm::vec3& position,
                           const glm::vec3& normal, size_t begin, size_t end, float split);

// Σ weight(r², r cos_receiver, r cos_vpl, A/π) Φ / π² over the VPLs [begin, end): the loop every
// VPL kernel shares, written out over plain floats so that the compiler vectorizes it.
// (cos_receiver cos_vpl / (r² + A/π) is weight(r2, cr, cv, a) = cr cv / (r2 (r2 + a)).)
template <typename Weight>
glm::vec3 sum_over_vpls(const VirtualPointLights& vpls, const glm::vec3& position,
                        const glm::vec3& normal, size_t begin, size_t end, Weight&& weight) {
  const glm::vec3* p = vpls.positions.data();
  const glm::vec3* n = vpls.normals.data();
  const glm::vec3* f = vpls.fluxes.data();
  const float* a = vpls.disk_areas.data();
  float sr = 0.0f, sg = 0.0f, sb = 0.0f;
  for (size_t v = begin; v < end; ++v) {
    const float dx = p[v].x - position.x, dy = p[v].y - position.y, dz = p[v].z - position.z;
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float cr = std::max(0.0f, normal.x * dx + normal.y * dy + normal.z * dz);
    const float cv = std::max(0.0f, -(n[v].x * dx + n[v].y * dy + n[v].z * dz));
    const float w = weight(r2, cr, cv, a[v]);
    sr += w * f[v].x;
    sg += w * f[v].y;
    sb += w * f[v].z;
  }
  constexpr float kInvPiSquared = 0.10132118364233778f;  // 1 / π²
  return glm::vec3(sr, sg, sb) * kInvPiSquared;
}

// One VPL's term of the above.
glm::vec3 vpl_term_over_pi(const VirtualPointLights& vpls, size_t v, const glm::vec3& position,
                           const glm::vec3& normal);

}  // namespace bakegi
