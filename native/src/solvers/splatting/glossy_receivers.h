// Glossy receivers in the preview (Nichols & Wyman 2009, §3.3.1 and §4.2 leave glossy light
// to per-VPL work): what the Phong lobe of a material (scene/phong_lobe.h) reflects towards
// the eye. It depends on the view, which the shared subsplats (irradiance, view-independent)
// do not hold, so it is gathered at every glossy pixel: direct light by light sampling plus
// one lobe-sampled ray (MIS, as the path tracer), and the bounce from every VPL through the
// lobe. The diffuse part of the same material stays with the splatted irradiance. Lobes
// wider than an exponent (a Principled BSDF's dielectric coat: 7.5) are folded into the
// diffuse albedo instead, energy kept for a uniform field (as antiradiance folds them): every
// pixel of such a scene would otherwise be glossy, and its wide lobe changes little.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/splatting/eye_gbuffer.h"
#include "solvers/splatting/virtual_point_lights.h"

namespace bakegi {

class DirectLight;

// Σ over the VPLs of the lobe's value f_g / ρ_g towards each VPL times the irradiance it
// sends (bounded by its own disk, as vpl_irradiance_over_pi): the radiance per unit ρ_g that
// a Phong lobe of `exponent` around the mirror direction `axis` reflects from the VPLs.
glm::vec3 vpl_glossy_reflection(const VirtualPointLights& vpls, const glm::vec3& position,
                                const glm::vec3& normal, const glm::vec3& axis, float exponent);

// Whether a pixel's lobe is gathered (exponent at least `fold_below`) rather than folded.
bool gathers_lobe(const EyeGBuffer& gbuffer, size_t pixel, float fold_below);

// The albedo that multiplies a pixel's diffuse light: its own plus its lobe's hemispherical
// albedo times ρ_g where the lobe is folded. Resizes `out`.
void folded_albedo(const EyeGBuffer& gbuffer, float fold_below, std::vector<glm::vec3>& out);

// The radiance the gathered glossy lobes reflect towards the eye at every pixel (0 where a
// pixel's lobe is folded or absent): direct light (`samples` light samples and lobe rays per
// pixel, seeded per pixel) plus the VPLs' bounce. Resizes `out`; returns how many pixels
// gather a lobe.
uint64_t glossy_reflection(const EyeGBuffer& gbuffer, const DirectLight& direct,
                           const VirtualPointLights& vpls, uint32_t samples, uint64_t seed,
                           float fold_below, std::vector<glm::vec3>& out);

}  // namespace bakegi
