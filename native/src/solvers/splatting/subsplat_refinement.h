// Subsplat refinement (Nichols & Wyman 2009, §3.3, §3.3.1, §4.2): a full-screen splat starts
// as one subsplat per texel of the coarsest level (the paper's 16^2) and each pass splits a
// subsplat into its four children where the min-max mipmap finds a discontinuity, until the
// finest level. One set serves every VPL (the paper's choice for diffuse scenes, §4.2).
// The illumination-guided variant (§3.3.1) refines separately for each VPL where its light
// differs between the four quadrants (illumination_refined_subsplats).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/splatting/min_max_mipmap.h"

namespace bakegi {

struct VirtualPointLights;

struct Subsplat {
  uint32_t level = 0;  // texels of 2^level pixels
  uint32_t x = 0, y = 0;
};

struct SubsplatSet {
  std::vector<Subsplat> subsplats;
  std::vector<uint64_t> per_level;  // count at each level, index = level
};

// The shared set: refined from `coarsest` down to `finest` (0 = pixels). Texels that see no
// surface are dropped.
SubsplatSet refine_subsplats(const MinMaxMipmap& mipmap, uint32_t coarsest, uint32_t finest,
                             const DiscontinuityTest& test);

// The shared set with a test on the summed light as well (the paper's §3.3.1 idea applied to
// all VPLs at once, for flat surfaces near bright VPLs, which no depth or normal test
// splits): level by level, each subsplat that the geometry keeps reads its light
// (`light` at MinMaxMipmap::point), and splits after all where the light's second difference to its
// neighbours of the same level, along x or y, exceeds `threshold` times its own light
// (bilinear interpolation is exact for light that changes linearly, so only curvature
// needs finer texels). Returns the set and each subsplat's light, in the same order.
SubsplatSet refine_subsplats_by_light(const MinMaxMipmap& mipmap, const EyeGBuffer& gbuffer,
                                      uint32_t coarsest, uint32_t finest,
                                      const DiscontinuityTest& test, float threshold,
                                      const SurfaceLight& light, std::vector<glm::vec3>& values);

// §3.3.1 for one VPL: starting from the coarsest texels, a subsplat splits while the VPL's
// light (vpl_term_over_pi at the four children's pixels) differs by more than `threshold`
// times their mean in any colour channel; each final subsplat is handed to `emit` with the
// VPL's light at its own pixel. Returns how many subsplats it emitted.
uint64_t illumination_refined_subsplats(
    const MinMaxMipmap& mipmap, const EyeGBuffer& gbuffer, const VirtualPointLights& vpls,
    size_t vpl, uint32_t coarsest, uint32_t finest, float threshold, float floor,
    const std::function<void(const Subsplat&, const glm::vec3&)>& emit);

}  // namespace bakegi
