// The scene as glTF 2.0 for the web page (issue 16, §4): one primitive per mesh and
// material, world space, each a progressive mesh (web/progressive_mesh.h) stored in plain
// glTF terms (its vertices coarse first, its faces in stream order: any glTF viewer shows
// the full mesh) plus, in the primitive's extras, what a streaming client needs on top:
//   "bakegi_progressive": {"parent": accessor (the vertex lookup table),
//                          "valid_at": accessor (per face), "level_vertices": [...]}.
// Axes: Y up, as glTF asks (a scene point (x, y, z) is (x, z, -y)); the grid keeps the
// scene's Z-up axes, which the page converts back to.
// Lights: point, spot and sun as KHR_lights_punctual (intensity in the core's units: W/sr,
// sun W/m^2, which three.js' physically based lights read as such), area lights (not in
// glTF) in the scene's extras with their radiance; materials as unlit-free metallic 0,
// roughness 1 base colours, emission in extras (radiance W/(m^2 sr)). Albedo textures
// become PNG images beside the file (8-bit sRGB) with TEXCOORD_0 (a textured primitive keeps
// a vertex per distinct corner uv).
// With the corners' grid reach (options.corner_reads_grid) every primitive carries
// _BAKEGI_READS_GRID, which the page multiplies into the grid's light.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace bakegi {

struct WebCamera {
  glm::vec3 position{0.0f};
  glm::vec4 rotation{0.0f, 0.0f, 0.0f, 1.0f};  // quaternion x, y, z, w: the camera looks down
                                               // -Z (scene axes, as Blender's camera)
  float yfov = 0.6911f;                        // radians (Blender's 50 mm on a 36 mm sensor)
  float aspect = 1.0f;
};

struct WebExportOptions {
  bool has_camera = false;
  WebCamera camera;
  std::string grid_file;  // the grid's file name beside scene.gltf ("" = none)
  // Which grid vertices each place sees (grid/grid_visibility_volume.h), beside scene.gltf
  // ("" = none: the page reads the grid as the paper does, through thin walls).
  std::string grid_visibility_file;
  // The grid has too many vertices for one (kMaxVisibilitySubvoxels): the page says so.
  bool grid_too_large_for_visibility = false;
  // The grid holds the light straight from the world and emitters as well as the bounced
  // light (IrradianceVectorGrid::emitted, added in): the page draws them from it.
  bool grid_has_emitted_light = false;
  // Empty, or per mesh per corner whether it reads the grid at all (web/corner_grid_reach.h):
  // written as the vertex attribute _BAKEGI_READS_GRID (float, 1 or 0), corners that differ
  // kept apart as vertices.
  std::vector<std::vector<uint8_t>> corner_reads_grid;
};

struct WebGltf {
  std::string json;          // scene.gltf
  std::vector<uint8_t> bin;  // scene.bin, which the JSON names
  std::vector<std::pair<std::string, std::vector<uint8_t>>> images;  // file name, PNG bytes
  size_t primitives = 0, vertices = 0, faces = 0;
};

// Throws Error(INVALID_ARGUMENT) for a scene whose meshes index past their vertices.
WebGltf encode_web_gltf(const SceneDescription& scene, const WebExportOptions& options);

}  // namespace bakegi
