// Least-squares seam stitching: after texels are resolved and dilated, the texels along
// each UV seam are nudged so that bilinear lookups on the two sides of the seam read the
// same value at the same point of the surface (the approach of Sloan's "Stitching UV
// seams", Bakery's and Godot's lightmappers).
//
// Why: the two sides of a seam are separate texels, each baked at its own samples up to a
// texel apart, so the renderer's bilinear lookups disagree along the seam and it shows as
// a line. Along each seam, points are taken at both ends and every half texel of the
// longer side between them; each point gives the 4-texel bilinear footprint on each side
// (texel centres at (i + 0.5) / W, as Blender's Linear interpolation reads, clamped at the
// border), and the constraint "side A reads what side B reads". Gauss-Seidel (Kaczmarz)
// sweeps then take the points in turn and make each constraint hold by the smallest
// change of its texels in the least-squares sense: with d = A - B and weights w (+ on A's
// texels, - on B's), t_i -= w_i d / sum(w^2). Where both footprints weigh alike (the
// usual case) both sides move to their mean m, t_i += w_i (m - v) / (sum over the side
// of w^2); where they do not (a footprint clamped at the border, or losing unfilled
// texels) the side whose weights are concentrated moves more. This orthogonal step keeps
// the texels closest to their baked values (on the Cornell atlas, sampled at midpoints:
// half the drift of moving both sides to the mean, and of its residual after 50 sweeps).
// Sweeps repeat until the largest mismatch is a small fraction of the values along the
// seams, or the pass limit.
//
// Limits: texels next to a seam also serve the chart's interior, which changes within a
// texel of the seam (the correction is spread over the footprint, no smoothness term);
// where charts meet at a vertex from several sides, or a texel serves two seams, the
// constraints can conflict and the sweeps stop at the pass limit with a residual; only
// texels that were filled (covered or dilated) move: a footprint texel still 0 outside
// every chart stays 0 (its weight is dropped); a point is not stitched where either side's
// filled texels weigh under 1/2 (it reads mostly unbaked zeros) or its covered texels
// under 1/4 (it reads only values dilated into texels rejected as inside geometry).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "lightmap/lightmap_seams.h"
#include "lightmap/exr_writer.h"

namespace bakegi {

struct SeamStitchOptions {
  uint32_t max_passes = 50;
  // Stop once the largest mismatch (any channel) is under this fraction of the largest
  // value read along the seams.
  float relative_tolerance = 1e-4f;
  // Seam points held and solved at once (84 bytes each: 84 MiB); more are solved in
  // batches one after the other, seams in order.
  size_t batch_points = size_t(1) << 20;
};

// At the seam points (the largest over the batches, each measured when it is solved).
struct SeamStitchReport {
  uint64_t points = 0;        // seam points stitched, each constraining both sides
  uint32_t passes = 0;        // Gauss-Seidel sweeps run (the most of any batch)
  float mismatch_before = 0;  // largest |side A - side B| (any channel) before stitching
  float mismatch_after = 0;   // and after
};

// Stitches `seams` (UVs of lightmap `image`) in place. covered: 1 per texel with samples
// (TexelSamples::covered); filled: 1 per texel that may change (the mask of resolve_texels
// after dilate_texels; texels not filled keep their value, 0 there). Costs O(seam points x
// passes) time and O(min(points, batch_points)) memory; no seams, no change. Throws
// Error(INTERNAL) if a mask's size differs from the image's.
SeamStitchReport stitch_seams(RgbImage& image, const std::vector<uint8_t>& covered,
                              const std::vector<uint8_t>& filled,
                              const std::vector<LightmapSeam>& seams,
                              const SeamStitchOptions& options = {});

// The bilinear lookup stitching makes agree (and tests check): texel centres at (i + 0.5) / W,
// coordinates clamped at the border.
glm::vec3 bilinear_lookup(const RgbImage& image, glm::vec2 uv);

}  // namespace bakegi
