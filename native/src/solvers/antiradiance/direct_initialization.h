// Direct light initialization of Antiradiance (§3.3): the solution starts from the light that
// surfaces reflect after one bounce of direct light (found with shadow rays elsewhere) plus
// what emissive surfaces emit, as exitant intensity, with NO antiradiance: direct shadows are
// already in E_direct, so nothing needs cancelling.
//
// At a patch of area a, unit face normal n, albedo ρ and emitted radiance L_e, for every bin
// (ω_j the direction light travels):
//
//   I_ex(ω_j) = a ⟨n|ω_j⟩₊ ((ρ/π) E_direct + L_e + ρ_g G(ω_j))
//
// where G, only at patches with a Phong lobe (Patch::glossy > 0), is the direct light binned
// by direction and reflected through the lobe as the local pass does (glossy_direct_reflection.h).
// The diffuse term is the same E_direct either way.
//
// Emission is one-sided (the front: surfaces bound solids, §3.1). It only seeds the transport:
// emitted and directly reflected light are direct light, not part of the indirect output, so
// the accumulated irradiance starts at zero. Clusters are then filled by pull().
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "lights/direct_light.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/glossy_direct_reflection.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

// Sets I_ex of every element from `direct_irradiance` (W/m², one per patch in
// ElementHierarchy::patches() order) (emission is direct light, not seeded here), then pulls; zeroes the
// accumulated irradiance. Diffuse only: without the light's directions, lobes get nothing. Throws
// Error(INVALID_ARGUMENT) on mismatched sizes.
void initialize_direct(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                       std::span<const glm::vec3> direct_irradiance, RadianceTables& tables);

// The direct light at the patches: E_direct at every patch and, at glossy ones, the same
// light split by the bin of its direction.
struct DirectLightAtPatches {
  std::vector<glm::vec3> irradiance;  // E_direct (W/m²) per patch
  // Patch p's binned light is binned[binned_offsets[p] .. binned_offsets[p + 1]) (empty for
  // patches without a lobe); its terms sum to irradiance[p] up to the light from behind the
  // face normal, which the lobe (on the face normal, as in the local pass) cannot reflect.
  std::vector<uint64_t> binned_offsets;  // patch_count + 1
  std::vector<BinnedIrradiance> binned;
  // Σ_s A(μ_s) E_s over the binned terms (A: the lobe's directional albedo per unit ρ_g at the
  // term's true direction): what the lobe reflects in all, per unit ρ_g; 0 without a lobe.
  std::vector<glm::vec3> glossy_reflectable;
};

// Initializes as above, the glossy term included: diffuse patches get exactly what the
// E_direct overload gives them. Throws Error(INVALID_ARGUMENT) on mismatched sizes.
void initialize_direct(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                       const DirectLightAtPatches& direct, RadianceTables& tables);

// direct_irradiance_at_patches (the same E_direct, bit for bit), plus the binned light of the
// patches with a lobe, whose samples hand their terms over with
// DirectLight::irradiance_sample_terms. The binned entries take at most m per glossy patch
// (fewer: one per bin the samples reached), the size of one I_ex row of RadianceTables.
DirectLightAtPatches direct_light_at_patches(const ElementHierarchy& hierarchy,
                                             const DirectionalBins& bins, const DirectLight& direct,
                                             int64_t samples, uint64_t seed, JobContext& context);

// E_direct at each patch centroid (face normal as geometric normal, the patch's shading
// normal for the lobe): the mean of `samples` DirectLight::irradiance_sample estimates, sample
// s of patch p drawn from sample_stream(seed, p, s), so the result does not depend on the
// thread count. Adds the shadow rays to the report's "rays" count; cancellable.
std::vector<glm::vec3> direct_irradiance_at_patches(const ElementHierarchy& hierarchy,
                                                    const DirectLight& direct, int64_t samples,
                                                    uint64_t seed, JobContext& context);

}  // namespace bakegi::antiradiance
