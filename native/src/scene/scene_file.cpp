#include "scene/scene_file.h"

#include <bit>
#include <cstring>

#include "scene/scene_validation.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/file_bytes.h"
#include "util/framed_file.h"

namespace bakegi {

namespace {

// A larger file is refused before it is read (the reader also bounds every count by it).
constexpr uint64_t kMaxSceneFileBytes = uint64_t(16) << 30;

constexpr char kMagic[8] = {'B', 'A', 'K', 'E', 'G', 'I', '\0', 'S'};

constexpr uint32_t kTextures = section_tag("TEXR"), kMaterials = section_tag("MATL"),
                   kMeshes = section_tag("MESH"), kLights = section_tag("LGHT"),
                   kWorld = section_tag("WRLD"), kPoints = section_tag("PNTS");

constexpr uint32_t kHasNormals = 1, kHasUvs = 2, kHasTriangleMaterials = 4;

// The shared little-endian writer and bounds-checked reader (util/byte_stream.h).
using Writer = ByteWriter;
using Reader = ByteReader;

void write_light(Writer& w, const Light& l) {
  w.u32(uint32_t(l.type));
  w.vec3(l.position);
  w.vec3(l.direction);
  w.vec3(l.axis_u);
  w.vec3(l.color);
  w.f32(l.radius);
  w.f32(l.spot_size);
  w.f32(l.spot_blend);
  w.f32(l.angle);
  w.u32(uint32_t(l.shape));
  w.f32(l.size_x);
  w.f32(l.size_y);
  w.u32(l.flags);
}

// Reads what write_light wrote (without the flags before version 4); `index` names it in
// errors.
Light read_light(Reader& r, bool has_flags, size_t index) {
  Light l;
  const uint32_t type = r.u32();
  l.position = r.vec3();
  l.direction = r.vec3();
  l.axis_u = r.vec3();
  l.color = r.vec3();
  l.radius = r.f32();
  l.spot_size = r.f32();
  l.spot_blend = r.f32();
  l.angle = r.f32();
  const uint32_t shape = r.u32();
  l.size_x = r.f32();
  l.size_y = r.f32();
  if (has_flags) l.flags = r.u32();
  try {
    l.type = light_type_from(type, index);
    l.shape = area_shape_from(shape, index);
  } catch (const Error& e) {
    r.fail(e.what());
  }
  return l;
}

void write_scene(Writer& w, const SceneDescription& scene) {
  size_t at = w.begin_section(kTextures);
  w.u32(uint32_t(scene.textures.size()));
  for (const Texture& t : scene.textures) {
    w.u32(t.width);
    w.u32(t.height);
    for (size_t i = 0, n = t.texel_count(); i < n; ++i) w.vec3(t.texel(i));
  }
  w.end_section(at);

  at = w.begin_section(kMaterials);
  w.u32(uint32_t(scene.materials.size()));
  for (const Material& m : scene.materials) {
    w.vec3(m.albedo);
    w.u32(m.albedo_texture);
    w.vec3(m.emission);
    w.u32(m.emission_two_sided ? 1 : 0);
    w.vec3(m.glossy);
    w.f32(m.glossy_exponent);
    w.u32(m.emission_texture);
    w.f32(m.opacity);
    w.u32(m.opacity_texture);
    w.f32(m.transmission);
    w.f32(m.transmission_ior);
  }
  w.end_section(at);

  at = w.begin_section(kMeshes);
  w.u32(uint32_t(scene.meshes.size()));
  for (const Mesh& m : scene.meshes) {
    w.u32(m.object_id);
    w.u32(m.material);
    w.u32(uint32_t(m.positions.size()));
    w.u32(uint32_t(m.indices.size() / 3));
    w.u32((m.corner_normals.empty() ? 0 : kHasNormals) | (m.corner_uvs.empty() ? 0 : kHasUvs) |
          (m.triangle_materials.empty() ? 0 : kHasTriangleMaterials));
    for (const glm::vec3& p : m.positions) w.vec3(p);
    for (uint32_t i : m.indices) w.u32(i);
    for (const glm::vec3& n : m.corner_normals) w.vec3(n);
    for (const glm::vec2& uv : m.corner_uvs) w.vec2(uv);
    for (uint32_t material : m.triangle_materials) w.u32(material);
  }
  w.end_section(at);

  at = w.begin_section(kLights);
  w.u32(uint32_t(scene.lights.size()));
  for (const Light& l : scene.lights) write_light(w, l);
  w.end_section(at);

  at = w.begin_section(kWorld);
  w.vec3(scene.world_radiance);
  w.u32(scene.world_texture.texture);
  w.vec3(scene.world_texture.scale);
  for (int c = 0; c < 3; ++c) w.vec3(scene.world_texture.rotation[c]);
  w.u32(uint32_t(scene.portals.size()));
  for (const Light& portal : scene.portals) write_light(w, portal);
  w.end_section(at);
}

void write_points(Writer& w, const BakePoints& points) {
  const size_t at = w.begin_section(kPoints);
  w.u64(points.size());
  for (const glm::vec3& p : points.positions) w.vec3(p);
  for (const glm::vec3& n : points.normals) w.vec3(n);
  for (uint32_t id : points.object_ids) w.u32(id);
  w.u64(points.share_candidates.size());
  for (uint32_t c : points.share_candidates) w.u32(c);
  w.end_section(at);
}

void read_world(Reader& r, SceneDescription& scene, uint32_t version) {
  scene.world_radiance = r.vec3();
  if (version < 6) return;
  scene.world_texture.texture = r.u32();
  scene.world_texture.scale = r.vec3();
  for (int c = 0; c < 3; ++c) scene.world_texture.rotation[c] = r.vec3();
  if (version < 7) return;
  const uint32_t count = r.u32();
  size_t index = 0;
  r.array(scene.portals, count, 84, "portals", [&] { return read_light(r, true, index++); });
}

void read_textures(Reader& r, SceneDescription& scene) {
  const uint32_t count = r.u32();
  r.need(count, 8, "textures");
  scene.textures.resize(count);
  for (Texture& t : scene.textures) {
    t.width = r.u32();
    t.height = r.u32();
    std::vector<glm::vec3> texels;
    r.array(texels, uint64_t(t.width) * t.height, 12, "texture pixels", [&] { return r.vec3(); });
    t.set_texels(std::move(texels));
  }
}

void read_materials(Reader& r, SceneDescription& scene, uint32_t version) {
  const uint32_t count = r.u32();
  const bool has_glossy = version >= 2, has_emission_texture = version >= 3;
  const bool has_passing = version >= 8;
  const uint64_t bytes = has_passing ? 68 : has_emission_texture ? 52 : has_glossy ? 48 : 32;
  r.array(scene.materials, count, bytes, "materials", [&] {
    Material m;
    m.albedo = r.vec3();
    m.albedo_texture = r.u32();
    m.emission = r.vec3();
    const uint32_t two_sided = r.u32();
    if (two_sided > 1) r.fail("material emission_two_sided must be 0 or 1");
    m.emission_two_sided = two_sided == 1;
    if (has_glossy) {
      m.glossy = r.vec3();
      m.glossy_exponent = r.f32();
    }
    if (has_emission_texture) m.emission_texture = r.u32();
    if (has_passing) {
      m.opacity = r.f32();
      m.opacity_texture = r.u32();
      m.transmission = r.f32();
      m.transmission_ior = r.f32();
    }
    return m;
  });
}

void read_meshes(Reader& r, SceneDescription& scene) {
  const uint32_t count = r.u32();
  r.need(count, 20, "meshes");
  scene.meshes.resize(count);
  for (Mesh& m : scene.meshes) {
    m.object_id = r.u32();
    m.material = r.u32();
    const uint64_t vertices = r.u32();
    const uint64_t triangles = r.u32();
    const uint32_t flags = r.u32();
    if (flags & ~uint32_t(kHasNormals | kHasUvs | kHasTriangleMaterials)) {
      r.fail("unknown mesh flags " + std::to_string(flags));
    }
    r.array(m.positions, vertices, 12, "mesh positions", [&] { return r.vec3(); });
    r.array(m.indices, 3 * triangles, 4, "mesh indices", [&] { return r.u32(); });
    if (flags & kHasNormals) {
      r.array(m.corner_normals, 3 * triangles, 12, "corner normals", [&] { return r.vec3(); });
    }
    if (flags & kHasUvs) {
      r.array(m.corner_uvs, 3 * triangles, 8, "corner uvs", [&] { return r.vec2(); });
    }
    if (flags & kHasTriangleMaterials) {
      r.array(m.triangle_materials, triangles, 4, "triangle materials", [&] { return r.u32(); });
    }
  }
}

void read_lights(Reader& r, SceneDescription& scene, uint32_t version) {
  const bool has_flags = version >= 4;
  const uint32_t count = r.u32();
  size_t index = 0;
  r.array(scene.lights, count, has_flags ? 84 : 80, "lights",
          [&] { return read_light(r, has_flags, index++); });
}

BakePoints read_points(Reader& r, uint32_t version) {
  BakePoints points;
  const uint64_t count = r.u64();
  r.need(count, 28, "bake points");
  r.array(points.positions, count, 12, "point positions", [&] { return r.vec3(); });
  r.array(points.normals, count, 12, "point normals", [&] { return r.vec3(); });
  r.array(points.object_ids, count, 4, "point object ids", [&] { return r.u32(); });
  if (version >= 5) {
    const uint64_t candidates = r.u64();
    r.need(candidates, 4, "share candidates");
    r.array(points.share_candidates, candidates, 4, "share candidates", [&] { return r.u32(); });
  }
  return points;
}

// The file must hold only what the C API accepts; anything else was not written by us.
void check_contents(const SceneFile& file, const std::string& name) {
  try {
    const SceneDescription& s = file.scene;
    for (size_t i = 0; i < s.textures.size(); ++i) check_texture(s.textures[i], i);
    for (size_t i = 0; i < s.materials.size(); ++i) check_material(s.materials[i], i);
    for (size_t i = 0; i < s.meshes.size(); ++i) check_mesh(s.meshes[i], i);
    for (size_t i = 0; i < s.lights.size(); ++i) check_light(s.lights[i], i);
    for (size_t i = 0; i < s.portals.size(); ++i) check_portal(s.portals[i], i);
    check_world(s.world_radiance);
    check_world_texture(s.world_texture);
    if (s.world_texture.is_set() && s.world_texture.texture >= s.textures.size()) {
      throw Error(BAKEGI_ERROR_INVALID_SCENE, "world texture index out of range");
    }
    if (file.points) check_bake_points(*file.points);
  } catch (const Error& e) {
    throw Error(BAKEGI_ERROR_BAD_FILE, name + ": holds an invalid scene: " + e.what());
  }
}

}  // namespace

std::vector<uint8_t> encode_scene_file(const SceneDescription& scene, const BakePoints* points) {
  Writer w = begin_framed_file(kMagic, kSceneFileVersion);
  write_scene(w, scene);
  if (points) write_points(w, *points);
  return finish_framed_file(w);
}

std::vector<uint8_t> encode_scene_sections(const SceneDescription& scene) {
  Writer w;
  write_scene(w, scene);
  return std::move(w.bytes);
}

SceneFile decode_scene_file(std::span<const uint8_t> bytes, const std::string& name) {
  auto fail = [&](const std::string& what) -> void {
    throw Error(BAKEGI_ERROR_BAD_FILE, name + ": " + what);
  };
  const FramedPayload framed = open_framed_file(bytes, kMagic, kOldestSceneFileVersion,
                                                kSceneFileVersion, "scene file", name);
  const uint32_t version = framed.version;
  SceneFile file;
  Reader r(framed.payload, name);
  const uint32_t order[] = {kTextures, kMaterials, kMeshes, kLights, kWorld, kPoints};
  for (uint32_t expected : order) {
    if (expected == kPoints && r.left() == 0) break;
    const uint32_t section = r.u32();
    r.u32();
    const uint64_t size = r.u64();
    if (section != expected) fail("unexpected section at byte " + std::to_string(r.position()));
    r.need(size, 1, "section");
    const size_t end = r.position() + size;
    if (expected == kTextures) read_textures(r, file.scene);
    if (expected == kMaterials) read_materials(r, file.scene, version);
    if (expected == kMeshes) read_meshes(r, file.scene);
    if (expected == kLights) read_lights(r, file.scene, version);
    if (expected == kWorld) read_world(r, file.scene, version);
    if (expected == kPoints) file.points = read_points(r, version);
    if (r.position() != end) fail("section size does not match its contents");
  }
  if (r.left() != 0) fail("unexpected bytes after the last section");
  check_contents(file, name);
  return file;
}

void write_scene_file(const std::string& path, const SceneDescription& scene,
                      const BakePoints* points) {
  // Atomic: a kill mid-write leaves the previous file whole.
  write_file_atomically(utf8_path(path), encode_scene_file(scene, points));
}

SceneFile read_scene_file(const std::string& path) {
  return decode_scene_file(read_file_bytes(utf8_path(path), kMaxSceneFileBytes), path);
}

}  // namespace bakegi
