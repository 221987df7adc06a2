// From baked samples to a lightmap image without black edges: samples are averaged into
// their texels (weighted by coverage), then the covered texels are dilated into the texels
// around them (the gutters between UV charts, and texels whose samples were rejected as
// inside geometry), so bilinear filtering and mipmaps at a chart's border read light from
// the chart, not black.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "lightmap/texel_rasterizer.h"
#include "lightmap/exr_writer.h"

namespace bakegi {

// Texel values: the coverage-weighted mean of each texel's samples (values: one RGB per
// sample of `samples`); texels without samples are 0. filled (out): 1 where a texel got a
// value.
RgbImage resolve_texels(const TexelSamples& samples, const glm::vec3* values,
                        std::vector<uint8_t>& filled);

// `passes` rounds of dilation: in each, every unfilled texel with a filled neighbour (8
// neighbours; diagonal ones weigh 1/2, they are farther) becomes the weighted mean of its
// filled neighbours and counts as filled from the next round on. After it, every texel
// within `passes` texels (chessboard distance) of a filled one is filled: no texel in the
// padding reads zero where a neighbour has light. Texels farther away stay 0.
void dilate_texels(RgbImage& image, std::vector<uint8_t>& filled, uint32_t passes);

}  // namespace bakegi
