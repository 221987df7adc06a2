// Which grid vertices a point sees, precomputed over space, for a reader that has no rays: the
// web page. Apply Grid asks with a shadow ray from each point to each vertex of its
// interpolation (grid_visibility.h); a fragment shader cannot. Without it the paper's reading
// (§3.2) blends vertices through walls thinner than a cell (docs/ivg.md: 47% NRMSE in the
// suite's two rooms against 12% with rays).
//
// The volume cuts every cell into `subdivision`^3 subvoxels (aligned with the trilinear cells,
// so the 8 vertices a subvoxel's points interpolate are the same for all of them) and stores
// two bytes per subvoxel:
//   mask      bit c set: vertex c of the subvoxel's trilinear cell (c = i + 2j + 4k offsets
//             from its lowest vertex) is valid and seen from some point of the subvoxel that
//             lies in open space (its centre and 8 points a quarter of the way to its
//             corners; a point whose rays meet a back face first, or reach an invalid vertex
//             unobstructed, is inside a solid and does not count). Subvoxels with no such point
//             take the union of the masks of their face neighbours in the same cell (a wall's face
//             at a subvoxel's edge leaves the subvoxel's points all inside the wall); with no such
//             neighbour either (deep in a solid, or where the grid's box ends on a surface facing
//             out: a room's outer wall, the top of the tallest object) the mask is full where the
//             world lights the scene (out there a sky: the paper's reading) and 0 where it is
//             black.
//   fallback  where the mask is 0, the nearest vertex of the 4^3 around the cell that a point
//             of the subvoxel (or of such a neighbour) sees, coded (di+1) | (dj+1) << 2 |
//             (dk+1) << 4 with d in -1..2 from the cell's lowest vertex; kNoFallback if none.
// A point reads the grid at q = p + offset * n (offset: one subvoxel, so that q's subvoxel
// lies off the point's own surface), from q's subvoxel: all 8 vertices where the mask is
// full (the paper's reading, which the page's texture unit does), the seen ones with their
// weights renormalised, the fallback vertex alone, or 0 (unsure: a face outside the rooms).
// Measured against references and against rays in docs/ivg.md.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "grid/grid_interpolation.h"
#include "grid/irradiance_vector_grid.h"

namespace bakegi {

class RayTracer;
struct Scene;

inline constexpr uint8_t kNoFallback = 0xff;
// What the web export builds: 8 subvoxels a cell for grids of 16 cells or fewer, above that
// about 1/64 of the grid's longest side (4 from 17 to 31 cells, 2 from 32). Measured
// (docs/ivg.md): at 16 cells 4 reads far better than 2 (maze 146% -> 100% NRMSE, two rooms
// 37% -> 20%) and 8 better again where gaps are thin (office wRRMSE 73% -> 51%, the other
// scenes within 0.2 points); at 32 cells 4 is no better than 2 and worse in the maze.
uint32_t page_visibility_subdivision(const GridLayout& layout);
// The most subvoxels a volume may hold (32 MB of codes; a 128^3 grid at 2 a cell). Larger
// grids are past what a page uploads anyway; the web export leaves their volume out.
inline constexpr size_t kMaxVisibilitySubvoxels = size_t(1) << 24;

struct GridVisibilityVolume {
  uint32_t subdivision = 2;
  std::array<uint32_t, 3> size{0, 0, 0};  // subvoxels along x, y, z: resolution * subdivision
  std::vector<uint8_t> codes;             // (mask, fallback) per subvoxel, x fastest

  size_t subvoxel_count() const { return size_t(size[0]) * size[1] * size[2]; }
};

// Builds the volume over `grid`'s layout (the scene's BVH in `tracer`); subdivision 2, 4, 6
// or 8 (even, so that subvoxels do not straddle a trilinear cell's boundary). 2 s^3 bytes a
// grid vertex (16 at 2; the grid itself: 217). world_lit: the scene's world is not black.
// Throws Error(OUT_OF_MEMORY) past kMaxVisibilitySubvoxels.
// cancelled (may be empty) is polled; when it returns true the build throws Error(CANCELLED).
GridVisibilityVolume build_grid_visibility_volume(const IrradianceVectorGrid& grid,
                                                  const Scene& scene, const RayTracer& tracer,
                                                  uint32_t subdivision, bool world_lit,
                                                  const std::function<bool()>& cancelled = {});

// How far along the normal the page reads the grid: one subvoxel (the largest cell side /
// subdivision).
float visibility_read_offset(const GridLayout& layout, uint32_t subdivision);

// The page's reading of the grid at (position, normal) (trilinear, `weights`), as described
// above. *unsure is set when the point reads 0 because it sees no vertex near it.
glm::vec3 evaluate_grid_with_volume(const IrradianceVectorGrid& grid,
                                    const GridVisibilityVolume& volume, const glm::vec3& position,
                                    const glm::vec3& normal, GridDirectionalWeights weights,
                                    bool* unsure = nullptr);

// The same at every point, in parallel; unsure (empty, or one per point) gets 1 where a point
// read 0 for seeing no vertex, else 0.
void evaluate_grid_with_volume(const IrradianceVectorGrid& grid, const GridVisibilityVolume& volume,
                               std::span<const glm::vec3> positions,
                               std::span<const glm::vec3> normals, GridDirectionalWeights weights,
                               std::span<glm::vec3> out, std::span<uint8_t> unsure);

// The file grid_visibility.bin beside the page's grid, little-endian:
//   char magic[8] = "BGIVIS1\0", u32 subdivision, u32 size[3], u32 resolution[3] (the grid's,
//   checked by readers), u64 raw bytes (2 per subvoxel), then the codes compressed as one
//   zlib stream (what the browser's DecompressionStream("deflate") reads).
std::vector<uint8_t> encode_visibility_file(const GridVisibilityVolume& volume,
                                            const GridLayout& layout);
// Throws Error(BAD_FILE) naming what is wrong, also when it does not fit `layout`.
GridVisibilityVolume decode_visibility_file(std::span<const uint8_t> bytes,
                                            const GridLayout& layout);

}  // namespace bakegi
