// Faces modelled back to back: two coplanar triangles with opposite normals at the same
// place (a plane duplicated with flipped normals, as game assets and "double-sided" exports
// model leaves, curtains and blind slats). Together they already form the zero-thickness
// solid that back_sides.h would make of a single plane, so neither may get a twin: with
// twins each side of the pair is present twice, reflects the light arriving there twice, and
// a room behind blinds modelled so came out 1.9x too bright.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace bakegi::antiradiance {

// Per triangle of scene.triangles: 1 when another triangle with the opposite normal lies in
// its plane (within a distance of 1e-4 of the scene's extent) and covers its centroid.
std::vector<uint8_t> backed_by_coincident_face(const Scene& scene);

}  // namespace bakegi::antiradiance
