// Which corners of the exported meshes read the grid at all, for the web page. The page reads
// the grid through the visibility volume (grid/grid_visibility_volume.h) one subvoxel off a
// surface, so it cannot tell a corner pressed against other geometry (a shelf's board on its
// back panel, a box's foot on the floor: the corner sees none of the grid's vertices) or
// buried under it (a floor under a box) from the open space a few centimetres out; those
// corners read the room's light there. Apply Grid's rays (grid/grid_visibility.h) know: they
// read 0 there, as the reference does. The export asks them once per corner and stores the
// answer per glTF vertex (1 reads, 0 reads nothing), which the page multiplies into the
// grid's light, interpolated across each face as a colour attribute is (docs/ivg.md: the
// office 54% -> 34% NRMSE, 123% -> 34% luminance-weighted).
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace bakegi {

class RayTracer;
struct IrradianceVectorGrid;

// Per mesh of `built.description`, per corner (3 per triangle): 1 where the corner (its
// position moved 0.2% towards its triangle's centre, as the add-on's bake points are; its
// corner normal or else its face's normal) reads the grid with Apply Grid's
// default lookup (visibility and buried points), 0 where it reads nothing. Degenerate
// triangles' corners read (1): no normal to judge by, and the page draws nothing there.
std::vector<std::vector<uint8_t>> corners_reading_grid(const IrradianceVectorGrid& grid,
                                                       const Scene& built, const RayTracer& tracer);

}  // namespace bakegi
