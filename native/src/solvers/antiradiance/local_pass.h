// The local pass of Antiradiance (§3.1 Eq. 18–19, §4.2): operators K and J at the patches,
// turning incident radiance L_in into exitant intensity I_ex = I_L − I_A.
//
// With ω_j the direction light travels (link.h), at a patch of area a and unit normal n:
//
//   E          = ω_bin Σ_l ⟨n|−ω_l⟩₊ L_in(ω_l)        irradiance from the front hemisphere
//   I_L(ω_j)   = a ⟨n|ω_j⟩₊ (ρ/π) E                    Eq. 18 for a diffuse BRDF ρ/π (§4.2)
//   I_A(ω_j)   = a ⟨n|−ω_j⟩₊ L_in(ω_j)                 Eq. 19: what arrived at the front goes
//                                                       on through the back along ω_j
//   I_ex(ω_j)  = I_L(ω_j) − I_A(ω_j)                   the two live in opposite hemispheres
//
// and E is added to the patch's accumulated irradiance (the output). Clusters are left alone:
// pull() rebuilds them afterwards. The normal is the face normal, the side that defines the
// solid (§3.1).
//
// Extension point for glossy materials: reflect_patch() dispatches per patch; a glossy lobe
// (Eq. 18 with a Phong or Lafortune f) adds a branch there that computes I_L from the full
// L_in row instead of from E. Only the diffuse path exists today.
#pragma once

#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/radiance_tables.h"

namespace bakegi::antiradiance {

// Runs K and J at every patch (in parallel, results independent of the thread count). Throws
// Error(INVALID_ARGUMENT) when the tables do not match the hierarchy or the bins.
void local_pass(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                RadianceTables& tables);

// The two halves of local_pass, for the asymmetric iteration (iteration.h), which solves the
// antiradiance of a bounce with its radiance frozen:
//
// K only: the front bins of every patch get I_L, the back bins 0 (the next bounce starts
// without antiradiance), and E is added to the accumulated irradiance.
void local_pass_radiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                              RadianceTables& tables);

// J only: the back bins of every patch get −I_A; the front bins and the accumulated irradiance
// are left alone. Returns the relative change of the back bins, Σ|new − old| / Σ|new| over
// patches, bins and channels (1 when they went to zero from non-zero, 0 when they stay zero).
double local_pass_antiradiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                                    RadianceTables& tables);

}  // namespace bakegi::antiradiance
