// bakegi_scene_*: copies what the caller passes into a SceneDescription, checking each
// element at the door so that errors name the call that caused them.
#include <cstring>
#include <limits>

#include "api/api_guard.h"
#include "api/handles.h"
#include "api/light_desc.h"
#include "scene/scene_validation.h"

using bakegi::Error;
using bakegi::guarded;
using bakegi::require;

namespace {

constexpr uint32_t kMaxElements = std::numeric_limits<uint32_t>::max() - 1;

void check_room(size_t count, const char* what) {
  if (count >= kMaxElements) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, std::string("too many ") + what);
  }
}

// A bakegi_light_desc as the core's Light, not yet checked; `index` names it in errors.
bakegi::Light light_from_desc(const bakegi_light_desc& light, size_t index) {
  auto v3 = [](const float* v) { return glm::vec3(v[0], v[1], v[2]); };
  // Read as integers: an out-of-range value must not be loaded as an enum.
  uint32_t raw_type = 0, raw_shape = 0;
  static_assert(sizeof(light.type) == sizeof raw_type && sizeof(light.shape) == sizeof raw_shape);
  std::memcpy(&raw_type, &light.type, sizeof raw_type);
  std::memcpy(&raw_shape, &light.shape, sizeof raw_shape);
  bakegi::Light l;
  l.type = bakegi::light_type_from(raw_type, index);
  l.position = v3(light.position);
  l.direction = v3(light.direction);
  l.axis_u = v3(light.axis_u);
  l.color = v3(light.color);
  l.radius = light.radius;
  l.spot_size = light.spot_size;
  l.spot_blend = light.spot_blend;
  l.angle = light.angle;
  l.shape = bakegi::area_shape_from(raw_shape, index);
  l.size_x = light.size_x;
  l.size_y = light.size_y;
  l.flags = light.flags;
  return l;
}

}  // namespace

extern "C" {

bakegi_status bakegi_scene_create(bakegi_scene** out_scene) {
  return guarded(__func__, [&] {
    require(out_scene, "out_scene");
    *out_scene = nullptr;
    *out_scene = bakegi::give_out(std::make_unique<bakegi_scene>());
  });
}

void bakegi_scene_destroy(bakegi_scene* scene) {
  bakegi::destroy_handle(scene);
}

bakegi_status bakegi_scene_add_texture(bakegi_scene* scene, uint32_t width, uint32_t height,
                                       const float* rgb_pixels, uint32_t* out_texture) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(rgb_pixels, "rgb_pixels");
    const size_t index = scene->description.textures.size();
    check_room(index, "textures");
    if (width == 0 || height == 0) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "texture " + std::to_string(index) + ": size must be at least 1x1, got " +
                      std::to_string(width) + "x" + std::to_string(height));
    }
    bakegi::Texture texture;
    texture.width = width;
    texture.height = height;
    const size_t count = size_t(width) * height;
    std::vector<glm::vec3> texels(count);
    for (size_t i = 0; i < count; ++i) {
      texels[i] = {rgb_pixels[3 * i], rgb_pixels[3 * i + 1], rgb_pixels[3 * i + 2]};
    }
    texture.set_texels(std::move(texels));
    bakegi::check_texture(texture, index);
    scene->description.textures.push_back(std::move(texture));
    if (out_texture) *out_texture = uint32_t(index);
  });
}

bakegi_status bakegi_scene_add_material(bakegi_scene* scene, const bakegi_material_desc* material,
                                        uint32_t* out_material) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(material, "material");
    const size_t index = scene->description.materials.size();
    check_room(index, "materials");
    if (material->emission_two_sided > 1) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "material " + std::to_string(index) +
                                                     ": emission_two_sided must be 0 or 1, got " +
                                                     std::to_string(material->emission_two_sided));
    }
    bakegi::Material m;
    m.albedo = {material->albedo[0], material->albedo[1], material->albedo[2]};
    m.albedo_texture = material->albedo_texture;
    m.emission = {material->emission[0], material->emission[1], material->emission[2]};
    m.emission_two_sided = material->emission_two_sided == 1;
    m.glossy = {material->glossy[0], material->glossy[1], material->glossy[2]};
    m.glossy_exponent = material->glossy_exponent;
    bakegi::check_material(m, index);
    scene->description.materials.push_back(m);
    if (out_material) *out_material = uint32_t(index);
  });
}

namespace {

// Material `material` of the scene, for setting a texture of `kind` (BAKEGI_NO_TEXTURE or an
// index below the texture count) on it; throws INVALID_ARGUMENT naming what is wrong.
bakegi::Material& material_with_texture(bakegi_scene* scene, uint32_t material, uint32_t texture,
                                        const char* kind) {
  require(scene, "scene");
  std::vector<bakegi::Material>& materials = scene->description.materials;
  if (material >= materials.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "material index " + std::to_string(material) +
                                                   " is not below the material count " +
                                                   std::to_string(materials.size()));
  }
  const size_t textures = scene->description.textures.size();
  if (texture != BAKEGI_NO_TEXTURE && texture >= textures) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "material " + std::to_string(material) + ": " + kind + " texture index " +
                    std::to_string(texture) + " is not below the texture count " +
                    std::to_string(textures) + " (add the texture first)");
  }
  return materials[material];
}

}  // namespace

bakegi_status bakegi_scene_set_material_emission_texture(bakegi_scene* scene, uint32_t material,
                                                         uint32_t texture) {
  return guarded(__func__, [&] {
    material_with_texture(scene, material, texture, "emission").emission_texture = texture;
  });
}

bakegi_status bakegi_scene_set_material_passing(bakegi_scene* scene, uint32_t material,
                                                float opacity, uint32_t opacity_texture,
                                                float transmission, float transmission_ior) {
  return guarded(__func__, [&] {
    bakegi::Material& stored = material_with_texture(scene, material, opacity_texture, "opacity");
    bakegi::Material m = stored;
    m.opacity = opacity;
    m.opacity_texture = opacity_texture;
    m.transmission = transmission;
    m.transmission_ior = transmission_ior;
    bakegi::check_material(m, material);
    stored = m;
  });
}

bakegi_status bakegi_scene_add_mesh(bakegi_scene* scene, const bakegi_mesh_desc* mesh,
                                    uint32_t* out_mesh) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(mesh, "mesh");
    const size_t index = scene->description.meshes.size();
    check_room(index, "meshes");
    const std::string name =
        "mesh " + std::to_string(index) + " (object " + std::to_string(mesh->object_id) + ")";
    auto require_array = [&](const void* array, const char* what) {
      if (!array) throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": " + what + " is NULL");
    };
    const size_t vertices = mesh->vertex_count, triangles = mesh->triangle_count;
    if (vertices > 0) require_array(mesh->positions, "positions");
    if (triangles > 0) require_array(mesh->indices, "indices");

    bakegi::Mesh m;
    m.material = mesh->material;
    m.object_id = mesh->object_id;
    m.positions.resize(vertices);
    for (size_t v = 0; v < vertices; ++v) {
      const float* p = mesh->positions + 3 * v;
      m.positions[v] = {p[0], p[1], p[2]};
    }
    m.indices.assign(mesh->indices, mesh->indices + 3 * triangles);
    if (mesh->corner_normals) {
      m.corner_normals.resize(3 * triangles);
      for (size_t c = 0; c < 3 * triangles; ++c) {
        const float* n = mesh->corner_normals + 3 * c;
        m.corner_normals[c] = {n[0], n[1], n[2]};
      }
    }
    if (mesh->corner_uvs) {
      m.corner_uvs.resize(3 * triangles);
      for (size_t c = 0; c < 3 * triangles; ++c) {
        m.corner_uvs[c] = {mesh->corner_uvs[2 * c], mesh->corner_uvs[2 * c + 1]};
      }
    }
    if (mesh->triangle_materials) {
      m.triangle_materials.assign(mesh->triangle_materials, mesh->triangle_materials + triangles);
    }
    bakegi::check_mesh(m, index);
    scene->description.meshes.push_back(std::move(m));
    if (out_mesh) *out_mesh = uint32_t(index);
  });
}

bakegi_status bakegi_scene_add_light(bakegi_scene* scene, const bakegi_light_desc* light,
                                     uint32_t* out_light) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(light, "light");
    const size_t index = scene->description.lights.size();
    check_room(index, "lights");
    const bakegi::Light l = light_from_desc(*light, index);
    bakegi::check_light(l, index);
    scene->description.lights.push_back(l);
    if (out_light) *out_light = uint32_t(index);
  });
}

bakegi_status bakegi_scene_get_light(const bakegi_scene* scene, uint32_t index,
                                     bakegi_light_desc* out_light) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(out_light, "out_light");
    const std::vector<bakegi::Light>& lights = scene->description.lights;
    if (index >= lights.size()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "light index " + std::to_string(index) +
                                                     " is not below the light count " +
                                                     std::to_string(lights.size()));
    }
    *out_light = bakegi::to_light_desc(lights[index]);
  });
}

bakegi_status bakegi_scene_clear_lights(bakegi_scene* scene) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    scene->description.lights.clear();
    scene->description.portals.clear();
  });
}

bakegi_status bakegi_scene_add_portal(bakegi_scene* scene, const bakegi_light_desc* portal) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(portal, "portal");
    const size_t index = scene->description.portals.size();
    check_room(index, "portals");
    bakegi::Light l = light_from_desc(*portal, index);
    bakegi::check_portal(l, index);
    l.color = glm::vec3(0.0f);  // a portal emits nothing
    l.flags = 0;
    l.spot_size = 0.0f;  // nor has a spread
    scene->description.portals.push_back(l);
  });
}

uint32_t bakegi_scene_portal_count(const bakegi_scene* scene) {
  return bakegi::live(scene) ? uint32_t(scene->description.portals.size()) : 0;
}

bakegi_status bakegi_scene_set_world(bakegi_scene* scene, const float radiance[3]) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(radiance, "radiance");
    const glm::vec3 value(radiance[0], radiance[1], radiance[2]);
    bakegi::check_world(value);
    scene->description.world_radiance = value;
  });
}

bakegi_status bakegi_scene_set_world_texture(bakegi_scene* scene, uint32_t texture,
                                             const float scale[3], const float* rotation) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    bakegi::WorldTexture world;
    if (texture != BAKEGI_NO_TEXTURE) {
      require(scale, "scale");
      const size_t textures = scene->description.textures.size();
      if (texture >= textures) {
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    "world texture index " + std::to_string(texture) +
                        " is not below the texture count " + std::to_string(textures) +
                        " (add the texture first)");
      }
      world.texture = texture;
      world.scale = glm::vec3(scale[0], scale[1], scale[2]);
      if (rotation) {
        for (int c = 0; c < 3; ++c) {
          world.rotation[c] = glm::vec3(rotation[3 * c], rotation[3 * c + 1], rotation[3 * c + 2]);
        }
      }
      bakegi::check_world_texture(world);
    }
    scene->description.world_texture = world;
  });
}

bakegi_status bakegi_scene_validate(const bakegi_scene* scene) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    bakegi::build_scene(scene->description);
  });
}

uint64_t bakegi_scene_triangle_count(const bakegi_scene* scene) {
  if (!bakegi::live(scene)) return 0;
  uint64_t count = 0;
  for (const bakegi::Mesh& mesh : scene->description.meshes) count += mesh.indices.size() / 3;
  return count;
}

bakegi_status bakegi_scene_get_bounds(const bakegi_scene* scene, float out_min[3],
                                      float out_max[3]) {
  return guarded(__func__, [&] {
    require(scene, "scene");
    require(out_min, "out_min");
    require(out_max, "out_max");
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-lo);
    for (const bakegi::Mesh& mesh : scene->description.meshes) {
      for (const glm::vec3& p : mesh.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
    }
    if (!(lo.x <= hi.x)) throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "the scene has no vertices");
    for (int a = 0; a < 3; ++a) {
      out_min[a] = lo[a];
      out_max[a] = hi[a];
    }
  });
}

uint32_t bakegi_scene_light_count(const bakegi_scene* scene) {
  return bakegi::live(scene) ? uint32_t(scene->description.lights.size()) : 0;
}

}  // extern "C"
