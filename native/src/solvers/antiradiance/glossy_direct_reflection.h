// The glossy part of the direct-light initialization (§3.3) at a patch with a Phong lobe: the
// direct light's incident directions binned, then reflected through the same lobe tables
// (glossy_lobe_table.h) and the same per-outgoing-bin normalization as the local pass's K
// (local_pass.h), with ω_j the direction light travels:
//
//   E_l        = Σ over the patch's E_direct terms whose light travels along bin l (W/m²,
//                receiver cosine included): the direct light split by direction
//   G(ω_j)     = A(⟨n|ω_j⟩) Σ_l t_l E_l / (ω_bin Σ_l t_l ⟨n|−ω_l⟩₊)
//                t: the lobe around the mirror image of ω_j; E_l / (ω_bin ⟨n|−ω_l⟩) is the
//                local pass's L_in(ω_l), written so that a bin straddling the horizon (centre
//                behind, light in front) neither divides by ~0 nor loses its light
//   then per channel G is scaled so that ω_bin Σ_j ⟨n|ω_j⟩₊ G(ω_j) = Σ_s A(μ_s) E_s
//                (over the terms s, μ_s the cosine of their true direction): the analytic
//                directional albedo of every incident direction, not of its bin centre, so
//                neither a lobe narrower than a bin nor the bins' quadrature creates or loses
//                energy, and I_ex,glossy(ω_j) = a ⟨n|ω_j⟩₊ ρ_g G(ω_j).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/glossy_lobe_table.h"

namespace bakegi::antiradiance {

// Direct irradiance (W/m², receiver cosine included) arriving with light travelling along the
// direction of `bin`.
struct BinnedIrradiance {
  uint16_t bin = 0;
  glm::vec3 irradiance{0.0f};
};

// G(ω_j) per unit ρ_g (W/(m² sr)) into `out` (m entries, 0 for bins behind the face normal)
// from the binned direct light `incident` (bins in any order, each at most once) and
// `reflectable` = Σ_s A(μ_s) E_s. `scratch` is resized to m.
void reflect_direct_glossy(const glm::vec3& normal, const DirectionalBins& bins,
                           const GlossyLobeTable& table, std::span<const BinnedIrradiance> incident,
                           const glm::vec3& reflectable, std::span<glm::vec3> out,
                           std::vector<glm::vec3>& scratch);

}  // namespace bakegi::antiradiance
