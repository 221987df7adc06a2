// The local pass of Antiradiance (§3.1 Eq. 18–19, §4.2): operators K and J at the patches,
// turning incident radiance L_in into exitant intensity I_ex = I_L − I_A.
//
// With ω_j the direction light travels (link.h), at a patch of area a and unit normal n:
//
//   E          = π Σ_l ⟨n|−ω_l⟩₊ L_in(ω_l) / Σ_l ⟨n|−ω_l⟩₊
//                                                   irradiance from the front hemisphere: the
//                                                   quadrature ω_bin Σ_l ⟨n|−ω_l⟩₊ L_in(ω_l)
//                                                   normalized so a uniform field gives π L
//                                                   (ω_bin Σ⟨n|−ω_l⟩₊ is off π by up to 0.7%
//                                                   at 192 bins, 2.8% at 48)
//   I_L(ω_j)   = a ⟨n|ω_j⟩₊ [(ρ_d/π) E + ρ_g G(ω_j)]  Eq. 18 for ρ_d/π plus the Phong lobe
//   G(ω_j)     = A(⟨n|ω_j⟩) Σ_l t_l ⟨n|−ω_l⟩₊ L_in(ω_l) / Σ_l t_l ⟨n|−ω_l⟩₊
//                                                   t: the lobe around the mirror image of ω_j
//                                                   integrated over the bins (glossy_lobe_table.h),
//                                                   A the analytic directional albedo; the row
//                                                   is then scaled so its flux equals
//                                                   Σ_l A(μ_l) E_l (no energy is created)
//   I_A(ω_j)   = a ⟨n|−ω_j⟩₊ L_in(ω_j)                 Eq. 19: what arrived at the front goes
//                                                       on through the back along ω_j
//   I_ex(ω_j)  = I_L(ω_j) − I_A(ω_j)                   the two live in opposite hemispheres
//
// and E is added to the patch's accumulated irradiance (the output). Clusters are left alone:
// pull() rebuilds them afterwards. The normal is the face normal, the side that defines the
// solid (§3.1).
//
// Patches without a glossy lobe (Patch::glossy = 0) take the diffuse fast path only; the
// glossy branch costs about Σ over front bins of the lobe's table size per patch.
#pragma once

#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

// Runs K and J at every patch (in parallel, results independent of the thread count). Throws
// Error(INVALID_ARGUMENT) when the tables do not match the hierarchy or the bins.
// `context` (optional) is checked for cancel every block of patches.
void local_pass(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                RadianceTables& tables, const JobContext* context = nullptr);

// The two halves of local_pass, for the asymmetric iteration (iteration.h), which solves the
// antiradiance of a bounce with its radiance frozen:
//
// K only: the front bins of every patch get I_L, the back bins 0 (the next bounce starts
// without antiradiance), and E is added to the accumulated irradiance.
void local_pass_radiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                              RadianceTables& tables, const JobContext* context = nullptr);

// J only: the back bins of every patch get −I_A; the front bins and the accumulated irradiance
// are left alone. Returns the relative change of the back bins, Σ|new − old| / Σ|new| over
// patches, bins and channels (1 when they went to zero from non-zero, 0 when they stay zero).
double local_pass_antiradiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                                    RadianceTables& tables, const JobContext* context = nullptr);

}  // namespace bakegi::antiradiance
