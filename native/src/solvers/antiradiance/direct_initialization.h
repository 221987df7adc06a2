// Direct light initialization of Antiradiance (§3.3): the solution starts from the light that
// surfaces reflect after one bounce of direct light (found with shadow rays elsewhere) plus
// what emissive surfaces emit, as exitant intensity, with NO antiradiance: direct shadows are
// already in E_direct, so nothing needs cancelling.
//
// At a patch of area a, unit face normal n, albedo ρ and emitted radiance L_e, for every bin
// (ω_j the direction light travels):
//
//   I_ex(ω_j) = a ⟨n|ω_j⟩₊ ((ρ/π) E_direct + L_e)
//
// Emission is one-sided (the front: surfaces bound solids, §3.1). It only seeds the transport:
// emitted and directly reflected light are direct light, not part of the indirect output, so
// the accumulated irradiance starts at zero. Clusters are then filled by pull().
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "direct/direct_light.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

// Sets I_ex of every element from `direct_irradiance` (W/m², one per patch in
// ElementHierarchy::patches() order) and the patches' emission, then pulls; zeroes the
// accumulated irradiance. Throws Error(INVALID_ARGUMENT) on mismatched sizes.
void initialize_direct(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                       std::span<const glm::vec3> direct_irradiance, RadianceTables& tables);

// E_direct at each patch centroid (face normal as geometric normal, the patch's shading
// normal for the lobe): the mean of `samples` DirectLight::irradiance_sample estimates, sample
// s of patch p drawn from sample_stream(seed, p, s), so the result does not depend on the
// thread count. Adds the shadow rays to the report's "rays" count; cancellable.
std::vector<glm::vec3> direct_irradiance_at_patches(const ElementHierarchy& hierarchy,
                                                    const DirectLight& direct, int64_t samples,
                                                    uint64_t seed, JobContext& context);

}  // namespace bakegi::antiradiance
