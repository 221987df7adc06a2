// The .bgs scene file: exactly what the C API received (textures, materials, meshes with
// their optional arrays, lights, world) and optionally a set of bake points, so that the
// CLI, tests and benchmarks run without Blender.
//
// Layout, all little-endian:
//   header   "BAKEGI\0S", u32 format version, u32 reserved (0), u64 payload bytes
//   payload  sections, each u32 tag, u32 reserved (0), u64 bytes, then its data:
//            TEXR textures, MATL materials, MESH meshes, LGHT lights, WRLD world
//            (all required, once each, in this order), then PNTS bake points (optional)
//   trailer  u64 FNV-1a 64 hash of header and payload
// Reading checks the hash and every size against the bytes that are left before it
// allocates, and rejects anything else with BAD_FILE.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scene/bake_points.h"
#include "scene/scene.h"

namespace bakegi {

// Version 2 added the glossy lobe to materials (48 bytes each instead of 32), version 3
// their emission texture (52 bytes), version 5 the bake points' share candidates, version 6
// the world's image (texture index, scale, rotation after the world's radiance), version 7
// the window portals (a count and light records after the rotation). Older files are still
// read: version 1 materials are diffuse, and neither has emission textures.
inline constexpr uint32_t kSceneFileVersion = 8;
inline constexpr uint32_t kOldestSceneFileVersion = 1;

struct SceneFile {
  SceneDescription scene;
  std::optional<BakePoints> points;
};

std::vector<uint8_t> encode_scene_file(const SceneDescription& scene, const BakePoints* points);
// The payload's scene sections (TEXR, MATL, MESH, LGHT, WRLD) without the frame or its
// checksum: what the precomputation cache hashes for its key.
std::vector<uint8_t> encode_scene_sections(const SceneDescription& scene);
// Throws Error(BAD_FILE) naming what is wrong; `name` is used in messages.
SceneFile decode_scene_file(std::span<const uint8_t> bytes, const std::string& name);

// Throw Error(IO) when the file cannot be written or read, Error(BAD_FILE) as above.
void write_scene_file(const std::string& path, const SceneDescription& scene,
                      const BakePoints* points);
SceneFile read_scene_file(const std::string& path);

}  // namespace bakegi
