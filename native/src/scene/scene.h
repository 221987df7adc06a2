// The scene as the core holds it: flat world-space triangles with per-corner shading data,
// materials, lights and world. Built by the C API (api/), read and written by scene_file,
// checked by scene_validation, traced through RayTracer.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bakegi/bakegi.h"
#include "scene/emission_cells.h"
#include "scene/mesh_topology.h"
#include "scene/shared_vector.h"
#include "scene/texel_palette.h"

namespace bakegi {

struct Texture {
  uint32_t width = 0, height = 0;

  // Linear RGB, row 0 at v = 0. Held as 8-bit indices into a palette where the texture has
  // at most 256 distinct values (every 8-bit image; texel_palette.h: exact, a quarter of the
  // bytes), else as floats (allow_palette false, or under 128 texels: floats always). Immutable
  // once set and shared by copies: every job copies the scene it bakes, and a relight compares it
  // with the previous one; Sponza's textures are 300 MB as floats, 75 MB as palettes.
  void set_texels(std::vector<glm::vec3> values, bool allow_palette = true);
  size_t texel_count() const {
    return palette_ ? palette_->indices.size() / 3 : floats_ ? floats_->size() : 0;
  }
  glm::vec3 texel(size_t i) const { return palette_ ? palette_->texel(i) : (*floats_)[i]; }
  // A copy of every texel (writing files, exports; lookups read texel()).
  std::vector<glm::vec3> texels() const;
  const TexelPalette* palette() const { return palette_.get(); }
  const glm::vec3* float_texels() const { return floats_ ? floats_->data() : nullptr; }
  size_t bytes() const {
    return palette_ ? palette_->bytes() : floats_ ? floats_->size() * sizeof(glm::vec3) : 0;
  }

  bool operator==(const Texture& other) const;

 private:
  std::shared_ptr<const std::vector<glm::vec3>> floats_;
  std::shared_ptr<const TexelPalette> palette_;
};

struct Material {
  glm::vec3 albedo{0.8f};
  uint32_t albedo_texture = BAKEGI_NO_TEXTURE;
  glm::vec3 emission{0.0f};                       // radiance W/(m^2 sr)
  uint32_t emission_texture = BAKEGI_NO_TEXTURE;  // multiplies emission where set
  bool emission_two_sided = true;
  // Optional modified Phong lobe (see bakegi_material_desc and scene/phong_lobe.h):
  // reflectance rho_g and exponent n; rho_g = 0 means a purely diffuse material.
  glm::vec3 glossy{0.0f};
  float glossy_exponent = 0.0f;
  // See-through surfaces (bakegi_scene_set_material_passing): where present (opacity x the
  // opacity texture's red channel), a `transmission` share of rays passes straight through; a
  // ray passes with probability 1 - present x (1 - transmission) and otherwise stops and
  // reflects as above (scene/passing_surfaces.h).
  float opacity = 1.0f;
  uint32_t opacity_texture = BAKEGI_NO_TEXTURE;
  float transmission = 0.0f;
  // > 0: glass of this index of refraction, whose share passing varies with the angle as
  // Fresnel says; `transmission` is then its cosine-weighted average (scene/fresnel.h).
  float transmission_ior = 0.0f;

  bool lets_light_pass() const {
    return opacity < 1.0f || opacity_texture != BAKEGI_NO_TEXTURE || transmission > 0.0f;
  }
  bool has_glossy() const { return glossy.x > 0 || glossy.y > 0 || glossy.z > 0; }
  bool is_emissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
  bool operator==(const Material&) const = default;
};

// One input mesh, kept as received (for scene files and messages).
struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;             // 3 per triangle
  std::vector<glm::vec3> corner_normals;     // empty or 3 per triangle
  std::vector<glm::vec2> corner_uvs;         // empty or 3 per triangle
  std::vector<uint32_t> triangle_materials;  // empty or 1 per triangle
  uint32_t material = 0;
  uint32_t object_id = 0;

  bool operator==(const Mesh&) const = default;
};

struct Light {
  bakegi_light_type type = BAKEGI_LIGHT_POINT;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};
  glm::vec3 axis_u{1.0f, 0.0f, 0.0f};
  glm::vec3 color{0.0f};
  float radius = 0.0f;
  float spot_size = 0.0f;
  float spot_blend = 0.0f;
  float angle = 0.0f;
  bakegi_area_shape shape = BAKEGI_AREA_SQUARE;
  float size_x = 0.0f;
  float size_y = 0.0f;
  uint32_t flags = 0;  // bakegi_light_flags
};

// The world's light from an equirectangular image (lights/environment_light.h): radiance
// = scale x the texture at the direction turned by `rotation` into the image's frame.
struct WorldTexture {
  uint32_t texture = BAKEGI_NO_TEXTURE;  // an index into SceneDescription::textures
  glm::vec3 scale{0.0f};
  glm::mat3 rotation{1.0f};  // world direction -> the image's frame (orthonormal)

  bool is_set() const { return texture != BAKEGI_NO_TEXTURE; }
  bool operator==(const WorldTexture&) const = default;
};

class EnvironmentLight;

// Everything the API received, before validation.
struct SceneDescription {
  std::vector<Texture> textures;
  std::vector<Material> materials;
  SharedVector<Mesh> meshes;  // shared by copies of the description (copy on write)
  std::vector<Light> lights;
  // A constant world; where world_texture is set, validation replaces it by the image's mean
  // (for the methods that take a constant world).
  glm::vec3 world_radiance{0.0f};
  WorldTexture world_texture;
  // Window portals (area-light shapes, BAKEGI_LIGHT_AREA) that guide the world's light
  // samples; they emit nothing (lights/world_portals.h).
  std::vector<Light> portals;
};

// A triangle ready for rendering: world positions, shading normals per corner, uvs.
struct Triangle {
  glm::vec3 p[3];
  glm::vec3 n[3];         // shading normals (face normal where none were given)
  glm::vec2 uv[3];        // (0,0) where none were given
  glm::vec3 face_normal;  // unit geometric normal, counter-clockwise winding
  float area = 0.0f;
  uint32_t material = 0;
  uint32_t mesh = 0;  // index into SceneDescription::meshes
  uint32_t mesh_triangle = 0;
};

// What shading a ray's hit needs of its triangle, 8 bytes beside Triangle's 124: a hit on a
// flat, untextured triangle reads only this (and the Hit's own position and normal), so the
// path tracer does not wait on a cache miss after every ray (docs/benchmarks.md, 0h).
struct TriangleShading {
  uint32_t material = 0;
  uint8_t smooth = 0;  // 1 where the corners' shading normals differ from the face normal
  // 1 where the triangle is so thin (twice its area under kSliverRelativeArea times its
  // longest edge squared) that Embree's float normal may point anywhere: the hit reads the
  // Triangle's face normal, computed in double.
  uint8_t sliver = 0;
};
inline constexpr double kSliverRelativeArea = 1e-3;

// The validated, flattened scene solvers work on. Degenerate triangles are dropped here
// (with a warning); everything else that is wrong is an error (see scene_validation.h).
struct Scene {
  SceneDescription description;
  std::vector<Triangle> triangles;
  std::vector<TriangleShading> shading;      // per triangle, as triangles
  std::vector<uint32_t> emissive_triangles;  // indices into triangles
  EmissionCells emission_cells;              // per emissive triangle (emission_cells.h)
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};
  std::vector<std::string> warnings;
  std::vector<MeshTopology> mesh_topology;  // per description.meshes entry (mesh_topology.h)
  // The world's image as a light, where description.world_texture is set (else null).
  std::shared_ptr<const EnvironmentLight> environment;

  const Material& material_of(const Triangle& t) const { return description.materials[t.material]; }
  // The same by index, from the compact shading record (no load of the Triangle).
  const Material& material_of(uint32_t triangle) const {
    return description.materials[shading[triangle].material];
  }
  float extent() const { return glm::length(bounds_max - bounds_min); }
  // Diffuse albedo at a point of a triangle (texture applied), barycentrics (b1, b2).
  glm::vec3 albedo_at(const Triangle& t, float b1, float b2) const;
  // The same by index: reads the Triangle only where the material has a texture.
  glm::vec3 albedo_at(uint32_t triangle, float b1, float b2) const;
  // Emitted radiance at a point of a triangle (emission texture applied), on its emitting
  // side(s); W/(m^2 sr).
  glm::vec3 emission_at(const Triangle& t, float b1, float b2) const;
};

// The share of a see-through material's surface present at a point of a triangle: opacity x
// its opacity texture's red channel there (1 for an opaque material); `textures` are those
// opacity_texture indexes.
float presence_at(const Material& material, const std::vector<Texture>& textures, const Triangle& t,
                  float b1, float b2);

}  // namespace bakegi
