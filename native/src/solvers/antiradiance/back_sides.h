// Back sides for open meshes. Antiradiance assumes every surface bounds a solid (§3.1): a
// surface receives only light arriving at its front (Fig. 7), and light crossing it from
// behind is cancelled by nobody. A single plane (a zero-thickness wall, a Blender "Plane")
// has a second side in the open, so the element hierarchy gives such triangles a twin patch
// at the same place with the flipped normal: together they form a zero-thickness solid. Twins
// never link to each other (their centers coincide and each lies in the other's plane, which
// link refinement drops), each receives and reflects light on its own side only and sends
// antiradiance to the other side, so light reaching the back of a plane is reflected there
// and blocked from going on.
//
// Not every triangle of an open mesh needs a twin: a room shell left open where another mesh
// closes it has its back inside the wall's material, the walls of a Cornell box made of
// planes have theirs towards an empty black world. A twin there only costs time, and one
// inside a closed region even leaks (light it receives from leaks goes out through surfaces
// that it meets from behind). So a triangle gets a twin only where its back faces open space,
// decided with kExposureRays fixed rays from four points of its back side:
// - a ray that escapes counts as open only when the world emits light (else nothing arrives
//   from there);
// - a ray that hits a back face is inside something (closed);
// - a ray that hits a front face at q counts as open unless the mirrored ray from q hits a
//   back face: this tells a room's inside (open) from the cavity under a box without a
//   bottom face, whose floor faces up into the box.
// The back side is open when at least kMinOpenFraction of the rays are. Rays are fixed, so
// the result is deterministic.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/ray_tracer.h"
#include "scene/scene.h"

namespace bakegi::antiradiance {

inline constexpr int kExposureRays = 16;
inline constexpr float kMinOpenFraction = 0.25f;

// Whether triangle t lies on a mesh that does not bound a solid (scene.mesh_topology; a scene
// without topology, built by hand, counts as closed).
bool on_open_mesh(const Scene& scene, const Triangle& t);

// The warnings for meshes that break the solid assumption, naming them as scene validation
// does ("mesh 3 (object 7)", which the add-on turns into the Blender object's name): one for
// open or non-manifold meshes, one for meshes with faces wound against their neighbours;
// each lists at most kMaxNamedMeshes meshes and counts the rest. Empty when all is closed.
// The open-mesh warning only when `back_sides_made`: an open surface whose back faces
// nothing (the walls of a room in a void) is exact as it is and not worth a warning.
inline constexpr size_t kMaxNamedMeshes = 6;
std::vector<std::string> open_mesh_warnings(const Scene& scene, bool back_sides_made);

// Per triangle of scene.triangles: 1 when it is on an open mesh and its back faces open space.
std::vector<uint8_t> exposed_back_sides(const Scene& scene, const RayTracer& tracer);

}  // namespace bakegi::antiradiance
