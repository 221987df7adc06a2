// Turning what the C API received (SceneDescription) into the Scene solvers work on, and
// refusing what cannot be rendered, with messages that name the element.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "scene/scene.h"

namespace bakegi {

// Checks of one element on its own, done at the C API's door (bakegi_scene_add_*) and
// again in build_scene. Throw bakegi::Error(INVALID_SCENE) for bad values and
// Error(INVALID_ARGUMENT) for bad enums; `index` is the element's index in the scene.
void check_texture(const Texture& texture, size_t index);
void check_material(const Material& material, size_t index);
void check_mesh(const Mesh& mesh, size_t index);  // not its material references
void check_light(const Light& light, size_t index);
// A window portal: an area light's shape (its colour and flags are not used).
void check_portal(const Light& portal, size_t index);
void check_world(const glm::vec3& radiance);
// The scale and rotation of a world image (its texture index is checked with the scene's).
void check_world_texture(const WorldTexture& world);

// Every position the core accepts (vertices, lights, bake points, position-valued settings)
// lies within +-1e12 m on each axis: beyond it float spacing exceeds 60 km, and Embree aborts
// the process on rays whose origin is huge. position_out_of_range_text says so for `v`.
bool position_in_range(const glm::vec3& v);
std::string position_out_of_range_text(const glm::vec3& v);

// Enums arrive as raw integers (C callers, files); a value outside the enum must be refused
// before it is stored in one. Throw Error(INVALID_ARGUMENT) naming light `index`.
bakegi_light_type light_type_from(uint32_t raw, size_t index);
bakegi_area_shape area_shape_from(uint32_t raw, size_t index);

// Validates the whole description and flattens it:
//  - every element is checked as above, and references (material -> texture,
//    mesh/triangle -> material) are in range;
//  - degenerate triangles (zero or negligible area) are dropped with one warning per mesh;
//  - shading normals are normalized (zero ones replaced by the face normal);
//  - emissive triangles are listed, with the cells light sampling picks on textured ones
//    (emission_cells.h);
//  - in the returned Scene::description, light directions are unit vectors, an area
//    light's axis_u is a unit vector orthogonal to its direction, and size_y equals
//    size_x for SQUARE and DISK lights;
//  - a scene without triangles, or without any light (no light of non-zero color, no
//    emissive triangle, black world), is refused with INVALID_SCENE.
Scene build_scene(const SceneDescription& description);

// Relighting: a scene with the lights and world of `description` and everything else
// (triangles, topology, textures) of `previous`, whose meshes, materials and textures the
// caller found equal to description's. Only lights and world are checked and normalized as
// in build_scene, so a relight of a large scene skips re-flattening it.
Scene build_relit_scene(const Scene& previous, const SceneDescription& description);

// Normalizes light directions and axes (see build_scene) and refuses a scene without light.
void normalize_lights_and_require_one(Scene& scene);

// Bytes the flattened scene will take (triangles and emissive list), before building it.
size_t estimate_scene_bytes(const SceneDescription& description);

}  // namespace bakegi

namespace bakegi {

struct BakePoints;

// Bake points: as many normals and object ids as positions, finite positions in range, unit
// normals (points are normalized when they enter the core, see api/). Throws
// Error(INVALID_ARGUMENT) naming the point.
void check_bake_points(const BakePoints& points);
// Share candidates (BakePoints::share_candidates): empty, or one per point, each naming
// itself or an earlier point that names itself.
void check_share_candidates(std::span<const uint32_t> candidates, size_t count);

}  // namespace bakegi
