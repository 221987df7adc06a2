#include "scene/scene_validation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "lights/environment_light.h"
#include "scene/bake_points.h"
#include "util/error.h"

namespace bakegi {

namespace {

// Texture values are factors in [0,1] (of albedo or emission); a little above 1 is float
// rounding of a 1.
constexpr float kTextureTolerance = 1e-4f;
// albedo + glossy <= 1: the same rounding slack for sums made by callers in single precision.
constexpr float kReflectanceTolerance = 1e-4f;
// Past ~1e6 cos^n is a mirror sharper than float directions resolve (1 - cos alpha ~ 1e-6).
constexpr float kMaxGlossyExponent = 1e6f;
// A triangle whose doubled area is below this fraction of its longest edge squared is a
// needle or a point: its normal is noise and it can receive no light. The threshold is
// about float precision (2^-23 ~ 1.2e-7).
constexpr double kDegenerateRelativeArea = 1e-7;

std::string num(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

std::string vec(const glm::vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%g, %g, %g)", v.x, v.y, v.z);
  return buffer;
}

[[noreturn]] void invalid(const std::string& message) {
  throw Error(BAKEGI_ERROR_INVALID_SCENE, message);
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite(const glm::vec2& v) {
  return std::isfinite(v.x) && std::isfinite(v.y);
}

// Coordinates beyond this are refused: there float spacing is over 60 km, so nothing could
// be baked, and Blender stores an infinite coordinate as FLT_MAX (3.4e38), which is finite.
constexpr float kMaxCoordinate = 1e12f;

const char* non_finite_word(const glm::vec3& v) {
  return std::isnan(v.x) || std::isnan(v.y) || std::isnan(v.z) ? "NaN" : "infinite";
}
const char* non_finite_word(const glm::vec2& v) {
  return std::isnan(v.x) || std::isnan(v.y) ? "NaN" : "infinite";
}

std::string mesh_name(const Mesh& mesh, size_t index) {
  return "mesh " + std::to_string(index) + " (object " + std::to_string(mesh.object_id) + ")";
}

const char* light_type_name(bakegi_light_type type) {
  switch (type) {
    case BAKEGI_LIGHT_POINT:
      return "point";
    case BAKEGI_LIGHT_SPOT:
      return "spot";
    case BAKEGI_LIGHT_SUN:
      return "sun";
    case BAKEGI_LIGHT_AREA:
      return "area";
  }
  return "unknown";
}

// The brightest light value (W, W/m^2 or W/(m^2 sr)) accepted: 12 orders of magnitude above
// the sun's irradiance, and low enough that a million such lights seen from a millimetre
// stay below FLT_MAX (3.4e38) through every solver's sums. A FLT_MAX emission used to pass
// and then overflow into an internal error or zeros.
constexpr float kMaxLightValue = 1e15f;

void check_color(const glm::vec3& color, const std::string& what) {
  if (!finite(color)) invalid(what + " is " + non_finite_word(color));
  if (color.x < 0 || color.y < 0 || color.z < 0) {
    invalid(what + " must not be negative, got " + vec(color));
  }
  if (color.x > kMaxLightValue || color.y > kMaxLightValue || color.z > kMaxLightValue) {
    invalid(what + " is " + vec(color) + ", above the brightest value bakegi bakes (" +
            num(kMaxLightValue) + "): float sums of it would overflow");
  }
}

void check_direction(const glm::vec3& direction, const std::string& what) {
  if (!finite(direction)) invalid(what + " is " + non_finite_word(direction));
  if (glm::length(glm::dvec3(direction)) < 1e-20) invalid(what + " is the zero vector");
}

bool is_positive(const glm::vec3& v) {
  return v.x > 0 || v.y > 0 || v.z > 0;
}

}  // namespace

void check_texture(const Texture& texture, size_t index) {
  const std::string name = "texture " + std::to_string(index);
  if (texture.width == 0 || texture.height == 0) {
    invalid(name + ": size must be at least 1x1, got " + std::to_string(texture.width) + "x" +
            std::to_string(texture.height));
  }
  const size_t count = texture.texel_count();
  if (count != size_t(texture.width) * texture.height) {
    invalid(name + ": holds " + std::to_string(count) + " pixels, expected " +
            std::to_string(size_t(texture.width) * texture.height));
  }
  // The pixel's name is built only for a bad pixel: per pixel it cost 2.7 s on Sponza.
  const auto where = [&](size_t i) {
    return name + ", pixel (" + std::to_string(i % texture.width) + ", " +
           std::to_string(i / texture.width) + ")";
  };
  for (size_t i = 0; i < count; ++i) {
    const glm::vec3 p = texture.texel(i);
    if (!finite(p)) invalid(where(i) + ": value is " + non_finite_word(p));
    if (p.x < 0 || p.y < 0 || p.z < 0 || p.x > 1 + kTextureTolerance ||
        p.y > 1 + kTextureTolerance || p.z > 1 + kTextureTolerance) {
      invalid(where(i) + ": value " + vec(p) +
              " is outside [0,1] (textures hold linear factors of a material's albedo or "
              "emission)");
    }
  }
}

void check_material(const Material& material, size_t index) {
  const std::string name = "material " + std::to_string(index);
  const glm::vec3& a = material.albedo;
  if (!finite(a)) invalid(name + ": albedo is " + non_finite_word(a));
  if (a.x < 0 || a.y < 0 || a.z < 0 || a.x > 1 || a.y > 1 || a.z > 1) {
    invalid(name + ": albedo must be in [0,1], got " + vec(a));
  }
  check_color(material.emission, name + ": emission");
  const glm::vec3& g = material.glossy;
  if (!finite(g)) invalid(name + ": glossy reflectance is " + non_finite_word(g));
  if (g.x < 0 || g.y < 0 || g.z < 0 || g.x > 1 || g.y > 1 || g.z > 1) {
    invalid(name + ": glossy reflectance must be in [0,1], got " + vec(g));
  }
  // Energy conservation of the sum of both lobes (each one's directional albedo is at most
  // its reflectance). A little slack for colors computed in single precision by callers.
  const glm::vec3 total = a + g;
  if (total.x > 1 + kReflectanceTolerance || total.y > 1 + kReflectanceTolerance ||
      total.z > 1 + kReflectanceTolerance) {
    invalid(name + ": albedo + glossy reflectance must not exceed 1 in any channel, got " + vec(a) +
            " + " + vec(g));
  }
  const float n = material.glossy_exponent;
  if (!std::isfinite(n) || n < 0 || n > kMaxGlossyExponent) {
    invalid(name + ": glossy exponent must be finite and in [0, " + num(kMaxGlossyExponent) +
            "], got " + num(n));
  }
  if (!std::isfinite(material.opacity) || material.opacity < 0 || material.opacity > 1) {
    invalid(name + ": opacity must be in [0,1], got " + num(material.opacity));
  }
  if (!std::isfinite(material.transmission) || material.transmission < 0 ||
      material.transmission > 1) {
    invalid(name + ": transmission must be in [0,1], got " + num(material.transmission));
  }
  const float ior = material.transmission_ior;
  if (!std::isfinite(ior) || (ior != 0.0f && (ior < 1.0f || ior > 10.0f))) {
    invalid(name + ": transmission IOR must be 0 (no Fresnel) or in [1, 10], got " + num(ior));
  }
}

void check_mesh(const Mesh& mesh, size_t index) {
  const std::string name = mesh_name(mesh, index);
  const size_t vertex_count = mesh.positions.size();
  if (mesh.indices.size() % 3 != 0) {
    invalid(name + ": index count " + std::to_string(mesh.indices.size()) +
            " is not a multiple of 3");
  }
  const size_t triangle_count = mesh.indices.size() / 3;
  for (size_t v = 0; v < vertex_count; ++v) {
    if (!finite(mesh.positions[v])) {
      invalid(name + ", vertex " + std::to_string(v) + ": position is " +
              non_finite_word(mesh.positions[v]));
    }
    if (!position_in_range(mesh.positions[v])) {
      invalid(name + ", vertex " + std::to_string(v) + ": " +
              position_out_of_range_text(mesh.positions[v]));
    }
  }
  for (size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= vertex_count) {
      invalid(name + ", triangle " + std::to_string(i / 3) + ": vertex index " +
              std::to_string(mesh.indices[i]) + " out of range (" + std::to_string(vertex_count) +
              " vertices)");
    }
  }
  if (!mesh.corner_normals.empty()) {
    if (mesh.corner_normals.size() != 3 * triangle_count) {
      invalid(name + ": " + std::to_string(mesh.corner_normals.size()) + " corner normals for " +
              std::to_string(triangle_count) + " triangles");
    }
    for (size_t c = 0; c < mesh.corner_normals.size(); ++c) {
      if (!finite(mesh.corner_normals[c])) {
        invalid(name + ", triangle " + std::to_string(c / 3) + ", corner " + std::to_string(c % 3) +
                ": normal is " + non_finite_word(mesh.corner_normals[c]));
      }
    }
  }
  if (!mesh.corner_uvs.empty()) {
    if (mesh.corner_uvs.size() != 3 * triangle_count) {
      invalid(name + ": " + std::to_string(mesh.corner_uvs.size()) + " corner uvs for " +
              std::to_string(triangle_count) + " triangles");
    }
    for (size_t c = 0; c < mesh.corner_uvs.size(); ++c) {
      if (!finite(mesh.corner_uvs[c])) {
        invalid(name + ", triangle " + std::to_string(c / 3) + ", corner " + std::to_string(c % 3) +
                ": uv is " + non_finite_word(mesh.corner_uvs[c]));
      }
    }
  }
  if (!mesh.triangle_materials.empty() && mesh.triangle_materials.size() != triangle_count) {
    invalid(name + ": " + std::to_string(mesh.triangle_materials.size()) +
            " triangle materials for " + std::to_string(triangle_count) + " triangles");
  }
}

namespace {

// check_light with the light's name in every message ("light 2 (area)", "portal 0").
void check_named_light(const Light& light, size_t index, const std::string& name) {
  switch (light.type) {
    case BAKEGI_LIGHT_POINT:
    case BAKEGI_LIGHT_SPOT:
    case BAKEGI_LIGHT_SUN:
    case BAKEGI_LIGHT_AREA:
      break;
    default:
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "light " + std::to_string(index) + ": unknown type " +
                      std::to_string(int(light.type)) + " (0 point, 1 spot, 2 sun, 3 area)");
  }
  check_color(light.color, name + ": color");
  if (light.type != BAKEGI_LIGHT_SUN && !finite(light.position)) {
    invalid(name + ": position is " + non_finite_word(light.position));
  }
  if (light.type != BAKEGI_LIGHT_SUN && !position_in_range(light.position)) {
    invalid(name + ": " + position_out_of_range_text(light.position));
  }
  if (light.type != BAKEGI_LIGHT_POINT) check_direction(light.direction, name + ": direction");
  if (light.flags & ~BAKEGI_LIGHT_KNOWN_FLAGS) {
    invalid(name + ": unknown flags " + std::to_string(light.flags & ~BAKEGI_LIGHT_KNOWN_FLAGS));
  }
  if (light.type == BAKEGI_LIGHT_POINT || light.type == BAKEGI_LIGHT_SPOT) {
    if (!(std::isfinite(light.radius) && light.radius >= 0)) {
      invalid(name + ": radius must be finite and >= 0, got " + num(light.radius));
    }
  }
  if (light.type == BAKEGI_LIGHT_SPOT) {
    if (!(light.spot_size > 0 && light.spot_size <= std::numbers::pi_v<float>)) {
      invalid(name + ": spot_size must be in (0, pi], got " + num(light.spot_size));
    }
    if (!(light.spot_blend >= 0 && light.spot_blend <= 1)) {
      invalid(name + ": spot_blend must be in [0, 1], got " + num(light.spot_blend));
    }
  }
  if (light.type == BAKEGI_LIGHT_SUN) {
    if (!(light.angle >= 0 && light.angle < std::numbers::pi_v<float>)) {
      invalid(name + ": angle must be in [0, pi), got " + num(light.angle));
    }
  }
  if (light.type == BAKEGI_LIGHT_AREA) {
    check_direction(light.axis_u, name + ": axis_u");
    const glm::dvec3 d = glm::normalize(glm::dvec3(light.direction));
    const glm::dvec3 u = glm::dvec3(light.axis_u);
    if (glm::length(u - glm::dot(u, d) * d) < 1e-6 * glm::length(u)) {
      invalid(name + ": axis_u " + vec(light.axis_u) + " is parallel to direction " +
              vec(light.direction));
    }
    switch (light.shape) {
      case BAKEGI_AREA_SQUARE:
      case BAKEGI_AREA_RECTANGLE:
      case BAKEGI_AREA_DISK:
      case BAKEGI_AREA_ELLIPSE:
        break;
      default:
        throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                    name + ": unknown shape " + std::to_string(int(light.shape)) +
                        " (0 square, 1 rectangle, 2 disk, 3 ellipse)");
    }
    if (!(std::isfinite(light.size_x) && light.size_x > 0)) {
      invalid(name + ": size_x must be finite and > 0, got " + num(light.size_x));
    }
    if (!(light.spot_size >= 0 && light.spot_size <= std::numbers::pi_v<float>)) {
      invalid(name + ": its spread (spot_size) must be in [0, pi], got " + num(light.spot_size));
    }
    const bool uses_size_y =
        light.shape == BAKEGI_AREA_RECTANGLE || light.shape == BAKEGI_AREA_ELLIPSE;
    if (uses_size_y && !(std::isfinite(light.size_y) && light.size_y > 0)) {
      invalid(name + ": size_y must be finite and > 0, got " + num(light.size_y));
    }
  }
}

}  // namespace

void check_light(const Light& light, size_t index) {
  check_named_light(light, index,
                    "light " + std::to_string(index) + " (" + light_type_name(light.type) + ")");
}

void check_portal(const Light& portal, size_t index) {
  const std::string name = "portal " + std::to_string(index);
  if (portal.type != BAKEGI_LIGHT_AREA) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, name + ": a portal is an area light's shape (type " +
                                                   std::to_string(int(BAKEGI_LIGHT_AREA)) +
                                                   "), got type " +
                                                   std::to_string(int(portal.type)));
  }
  Light shape = portal;
  shape.color = glm::vec3(0.0f);
  shape.flags = 0;
  check_named_light(shape, index, name);
}

bakegi_light_type light_type_from(uint32_t raw, size_t index) {
  if (raw > BAKEGI_LIGHT_AREA) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "light " + std::to_string(index) +
                                                   ": unknown type " + std::to_string(raw) +
                                                   " (0 point, 1 spot, 2 sun, 3 area)");
  }
  return bakegi_light_type(raw);
}

bakegi_area_shape area_shape_from(uint32_t raw, size_t index) {
  if (raw > BAKEGI_AREA_ELLIPSE) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "light " + std::to_string(index) +
                                                   ": unknown shape " + std::to_string(raw) +
                                                   " (0 square, 1 rectangle, 2 disk, 3 ellipse)");
  }
  return bakegi_area_shape(raw);
}

void check_world(const glm::vec3& radiance) {
  check_color(radiance, "world radiance");
}

void check_world_texture(const WorldTexture& world) {
  if (!world.is_set()) return;
  check_color(world.scale, "world texture scale");
  // Orthonormal to within float rounding: the image's directions must stay unit vectors.
  for (int c = 0; c < 3; ++c) {
    if (!finite(world.rotation[c])) invalid("world texture rotation is not finite");
  }
  const glm::dmat3 r(world.rotation);
  const glm::dmat3 product = glm::transpose(r) * r;
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(product[c][k] - (c == k ? 1.0 : 0.0)) > 1e-4) {
        invalid("world texture rotation is not a rotation (its columns are not orthonormal)");
      }
    }
  }
}

size_t estimate_scene_bytes(const SceneDescription& description) {
  size_t triangles = 0;
  for (const Mesh& mesh : description.meshes) triangles += mesh.indices.size() / 3;
  size_t bytes = triangles * (sizeof(Triangle) + sizeof(TriangleShading) + sizeof(uint32_t));
  // A world image's sampling tables: about two floats per texel (lights/environment_light.h).
  const WorldTexture& world = description.world_texture;
  if (world.is_set() && world.texture < description.textures.size()) {
    const Texture& image = description.textures[world.texture];
    bytes += 2 * sizeof(float) * (size_t(image.width) + 1) * size_t(image.height);
  }
  return bytes;
}

namespace {

// Textures, materials (and their texture indices), lights and world, in that order.
void check_scene_parts(const SceneDescription& description) {
  for (size_t i = 0; i < description.textures.size(); ++i) {
    check_texture(description.textures[i], i);
  }
  for (size_t i = 0; i < description.materials.size(); ++i) {
    const Material& material = description.materials[i];
    check_material(material, i);
    if (material.albedo_texture != BAKEGI_NO_TEXTURE &&
        material.albedo_texture >= description.textures.size()) {
      invalid("material " + std::to_string(i) + ": texture index " +
              std::to_string(material.albedo_texture) + " out of range (" +
              std::to_string(description.textures.size()) + " textures)");
    }
    if (material.emission_texture != BAKEGI_NO_TEXTURE &&
        material.emission_texture >= description.textures.size()) {
      invalid("material " + std::to_string(i) + ": emission texture index " +
              std::to_string(material.emission_texture) + " out of range (" +
              std::to_string(description.textures.size()) + " textures)");
    }
    if (material.opacity_texture != BAKEGI_NO_TEXTURE &&
        material.opacity_texture >= description.textures.size()) {
      invalid("material " + std::to_string(i) + ": opacity texture index " +
              std::to_string(material.opacity_texture) + " out of range (" +
              std::to_string(description.textures.size()) + " textures)");
    }
  }
  for (size_t i = 0; i < description.lights.size(); ++i) check_light(description.lights[i], i);
  for (size_t i = 0; i < description.portals.size(); ++i) check_portal(description.portals[i], i);
  check_world(description.world_radiance);
  check_world_texture(description.world_texture);
  if (description.world_texture.is_set() &&
      description.world_texture.texture >= description.textures.size()) {
    invalid("world texture index " + std::to_string(description.world_texture.texture) +
            " out of range (" + std::to_string(description.textures.size()) + " textures)");
  }
}

// The world's image as a light, its mean standing in for the constant world.
void build_environment(Scene& scene) {
  scene.environment.reset();
  const WorldTexture& world = scene.description.world_texture;
  if (!world.is_set()) return;
  auto environment = std::make_shared<const EnvironmentLight>(world, scene.description.textures);
  scene.description.world_radiance = environment->mean_radiance();
  scene.environment = std::move(environment);
}

// Checks every mesh and returns their triangle count (refused beyond 32-bit indices).
size_t checked_triangle_count(const SceneDescription& description) {
  size_t total_triangles = 0;
  for (size_t m = 0; m < description.meshes.size(); ++m) {
    check_mesh(description.meshes[m], m);
    total_triangles += description.meshes[m].indices.size() / 3;
  }
  if (total_triangles >= std::numeric_limits<uint32_t>::max()) {
    invalid("the scene has " + std::to_string(total_triangles) +
            " triangles; at most 4294967294 are supported");
  }
  return total_triangles;
}

std::string material_out_of_range(uint32_t material, size_t material_count) {
  return "material index " + std::to_string(material) + " out of range (" +
         std::to_string(material_count) + " materials)";
}

// Appends mesh m's triangles (degenerate ones dropped, with a warning) to the scene;
// returns how many were dropped.
size_t append_mesh_triangles(Scene& scene, size_t m) {
  const SceneDescription& description = scene.description;
  const Mesh& mesh = description.meshes[m];
  const size_t material_count = description.materials.size();
  const size_t triangle_count = mesh.indices.size() / 3;
  if (triangle_count == 0) return 0;
  if (mesh.triangle_materials.empty() && mesh.material >= material_count) {
    invalid(mesh_name(mesh, m) + ": " + material_out_of_range(mesh.material, material_count));
  }
  size_t dropped = 0;
  bool textured_without_uvs = false;
  for (size_t t = 0; t < triangle_count; ++t) {
    Triangle tri;
    tri.material = mesh.triangle_materials.empty() ? mesh.material : mesh.triangle_materials[t];
    if (tri.material >= material_count) {
      invalid(mesh_name(mesh, m) + ", triangle " + std::to_string(t) + ": " +
              material_out_of_range(tri.material, material_count));
    }
    for (int c = 0; c < 3; ++c) tri.p[c] = mesh.positions[mesh.indices[3 * t + c]];
    // In double: the cross product of nearby float points loses most of its digits.
    const glm::dvec3 e1 = glm::dvec3(tri.p[1]) - glm::dvec3(tri.p[0]);
    const glm::dvec3 e2 = glm::dvec3(tri.p[2]) - glm::dvec3(tri.p[0]);
    const glm::dvec3 e3 = glm::dvec3(tri.p[2]) - glm::dvec3(tri.p[1]);
    const glm::dvec3 cross = glm::cross(e1, e2);
    const double twice_area = glm::length(cross);
    const double longest2 = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
    if (!(twice_area > kDegenerateRelativeArea * longest2) || twice_area == 0.0) {
      ++dropped;
      continue;
    }
    tri.face_normal = glm::vec3(cross / twice_area);
    tri.area = float(0.5 * twice_area);
    for (int c = 0; c < 3; ++c) {
      glm::vec3 n = tri.face_normal;
      if (!mesh.corner_normals.empty()) {
        const glm::dvec3 given(mesh.corner_normals[3 * t + c]);
        const double length = glm::length(given);
        if (length > 1e-20) n = glm::vec3(given / length);
      }
      tri.n[c] = n;
      tri.uv[c] = mesh.corner_uvs.empty() ? glm::vec2(0.0f) : mesh.corner_uvs[3 * t + c];
    }
    tri.mesh = uint32_t(m);
    tri.mesh_triangle = uint32_t(t);
    const Material& material = description.materials[tri.material];
    if (mesh.corner_uvs.empty() && (material.albedo_texture != BAKEGI_NO_TEXTURE ||
                                    material.emission_texture != BAKEGI_NO_TEXTURE)) {
      textured_without_uvs = true;
    }
    if (material.is_emissive()) {
      scene.emissive_triangles.push_back(uint32_t(scene.triangles.size()));
    }
    const bool smooth =
        tri.n[0] != tri.face_normal || tri.n[1] != tri.face_normal || tri.n[2] != tri.face_normal;
    const bool sliver = twice_area < kSliverRelativeArea * longest2;
    scene.shading.push_back({tri.material, uint8_t(smooth ? 1 : 0), uint8_t(sliver ? 1 : 0)});
    scene.triangles.push_back(tri);
  }
  if (dropped > 0) {
    scene.warnings.push_back(mesh_name(mesh, m) + ": " + std::to_string(dropped) + " of " +
                             std::to_string(triangle_count) +
                             " triangles dropped as degenerate (zero area)");
  }
  if (textured_without_uvs) {
    scene.warnings.push_back(mesh_name(mesh, m) +
                             " uses a textured material but has no UVs; the texture is "
                             "sampled at uv (0, 0)");
  }
  return dropped;
}

void compute_bounds(Scene& scene) {
  scene.bounds_min = scene.bounds_max = scene.triangles[0].p[0];
  for (const Triangle& tri : scene.triangles) {
    for (const glm::vec3& p : tri.p) {
      scene.bounds_min = glm::min(scene.bounds_min, p);
      scene.bounds_max = glm::max(scene.bounds_max, p);
    }
  }
}

}  // namespace

Scene build_scene(const SceneDescription& description) {
  check_scene_parts(description);
  Scene scene;
  scene.description = description;
  scene.triangles.reserve(checked_triangle_count(description));
  scene.shading.reserve(scene.triangles.capacity());

  size_t dropped_total = 0;
  for (size_t m = 0; m < description.meshes.size(); ++m) {
    const Mesh& mesh = description.meshes[m];
    scene.mesh_topology.push_back(analyze_mesh_topology(mesh.positions, mesh.indices));
    dropped_total += append_mesh_triangles(scene, m);
  }
  if (scene.triangles.empty()) {
    if (dropped_total > 0) {
      invalid("the scene is empty: all " + std::to_string(dropped_total) +
              " triangles are degenerate (zero area)");
    }
    invalid("the scene is empty: it has no triangles");
  }

  build_environment(scene);
  normalize_lights_and_require_one(scene);
  scene.emission_cells = build_emission_cells(scene);
  compute_bounds(scene);
  return scene;
}

Scene build_relit_scene(const Scene& previous, const SceneDescription& description) {
  for (size_t i = 0; i < description.lights.size(); ++i) check_light(description.lights[i], i);
  for (size_t i = 0; i < description.portals.size(); ++i) check_portal(description.portals[i], i);
  check_world(description.world_radiance);
  check_world_texture(description.world_texture);
  if (description.world_texture.is_set() &&
      description.world_texture.texture >= previous.description.textures.size()) {
    invalid("world texture index " + std::to_string(description.world_texture.texture) +
            " out of range");
  }
  Scene scene = previous;
  scene.description.lights = description.lights;
  scene.description.world_radiance = description.world_radiance;
  scene.description.world_texture = description.world_texture;
  scene.description.portals = description.portals;
  build_environment(scene);
  normalize_lights_and_require_one(scene);
  return scene;
}

void normalize_lights_and_require_one(Scene& scene) {
  bool has_light =
      is_positive(scene.description.world_radiance) || !scene.emissive_triangles.empty();
  size_t dark_lights = 0;
  for (Light& light : scene.description.lights) {
    has_light = has_light || is_positive(light.color);
    dark_lights += is_positive(light.color) ? 0 : 1;
    if (light.type != BAKEGI_LIGHT_POINT) {
      light.direction = glm::vec3(glm::normalize(glm::dvec3(light.direction)));
    }
    if (light.type == BAKEGI_LIGHT_AREA) {
      const glm::dvec3 d(light.direction);
      const glm::dvec3 u(light.axis_u);
      light.axis_u = glm::vec3(glm::normalize(u - glm::dot(u, d) * d));
      if (light.shape == BAKEGI_AREA_SQUARE || light.shape == BAKEGI_AREA_DISK) {
        light.size_y = light.size_x;
      }
    }
  }
  if (!has_light && dark_lights > 0) {
    invalid("no light: the scene's " + std::to_string(dark_lights) +
            (dark_lights == 1 ? " light has" : " lights have") +
            " zero power or a black color, and it has no emissive material and a black world");
  }
  if (!has_light) {
    invalid("no light: the scene has no lights, no emissive material and a black world");
  }
}

}  // namespace bakegi

namespace bakegi {

bool position_in_range(const glm::vec3& v) {
  return std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate &&
         std::abs(v.z) <= kMaxCoordinate;
}

std::string position_out_of_range_text(const glm::vec3& v) {
  return "position " + vec(v) + " is out of range: coordinates must be within +-1e12 m";
}

void check_bake_points(const BakePoints& points) {
  const size_t count = points.positions.size();
  if (points.normals.size() != count || points.object_ids.size() != count) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "bake points: " + std::to_string(count) + " positions but " +
                    std::to_string(points.normals.size()) + " normals and " +
                    std::to_string(points.object_ids.size()) + " object ids");
  }
  for (size_t i = 0; i < count; ++i) {
    const std::string name = "bake point " + std::to_string(i);
    if (!finite(points.positions[i])) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  name + ": position is " + non_finite_word(points.positions[i]));
    }
    if (!position_in_range(points.positions[i])) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  name + ": " + position_out_of_range_text(points.positions[i]));
    }
    if (!finite(points.normals[i])) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  name + ": normal is " + non_finite_word(points.normals[i]));
    }
    const float length = glm::length(points.normals[i]);
    if (!(std::abs(length - 1.0f) < 1e-3f)) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  name + ": normal " + vec(points.normals[i]) + " is not unit length");
    }
  }
  check_share_candidates(points.share_candidates, count);
}

void check_share_candidates(std::span<const uint32_t> candidates, size_t count) {
  if (candidates.empty()) return;
  if (candidates.size() != count) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "share candidates: " + std::to_string(candidates.size()) + " for " +
                    std::to_string(count) + " bake points");
  }
  for (size_t i = 0; i < count; ++i) {
    const uint32_t c = candidates[i];
    // Earlier points only, and each group's first point names itself: one pass then finds
    // every group, and no chain or cycle can form.
    if (c > i || candidates[c] != c) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "share candidates: bake point " + std::to_string(i) + " names " +
                      std::to_string(c) +
                      (c > i ? ", a later point" : ", which names another point itself"));
    }
  }
}

}  // namespace bakegi
