#include "web/gltf_export.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <sstream>
#include <tuple>

#include "bakegi/bakegi.h"
#include "json_text.h"
#include "util/error.h"
#include "web/progressive_mesh.h"

// stb_image_write (Debian's libstb-dev), compiled here, private to this file.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace bakegi {

namespace {

constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

std::string vec(const float* v, int n) {
  std::string s = "[";
  for (int i = 0; i < n; ++i) {
    if (i) s += ',';
    s += json_number(v[i]);
  }
  return s + "]";
}
std::string vec3(const glm::vec3& v) {
  return vec(&v.x, 3);
}

// Accumulates the binary buffer, its views and accessors.
class BufferBuilder {
 public:
  // A view + accessor of `count` elements of `type` ("VEC3", "SCALAR"); returns the accessor.
  int add(const void* data, size_t bytes, size_t count, int component, const char* type, int target,
          const std::string& bounds = "") {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    bin.resize(offset + bytes);
    if (bytes) std::memcpy(bin.data() + offset, data, bytes);
    views.push_back("{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
                    ",\"byteLength\":" + std::to_string(bytes) +
                    (target ? ",\"target\":" + std::to_string(target) : "") + "}");
    accessors.push_back("{\"bufferView\":" + std::to_string(views.size() - 1) +
                        ",\"componentType\":" + std::to_string(component) + ",\"count\":" +
                        std::to_string(count) + ",\"type\":\"" + type + "\"" + bounds + "}");
    return int(accessors.size() - 1);
  }
  std::vector<uint8_t> bin;
  std::vector<std::string> views, accessors;
};

// glTF is Y-up: a point (x, y, z) of the scene (Z-up, Blender's axes) is (x, z, -y) there, a
// turn of -90 degrees about x (what Blender's glTF exporter does too).
glm::vec3 to_gltf(const glm::vec3& v) {
  return {v.x, v.z, -v.y};
}
constexpr float kHalfSqrt2 = 0.70710678f;

// Quaternion product a * b, (x, y, z, w).
glm::vec4 multiply(const glm::vec4& a, const glm::vec4& b) {
  return {
      a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
      a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

// A quaternion turning -Z onto `direction` (glTF lights and cameras look down -Z).
glm::vec4 rotation_to(const glm::vec3& direction) {
  const glm::vec3 from(0.0f, 0.0f, -1.0f);
  const glm::vec3 to = glm::normalize(direction);
  const float d = glm::dot(from, to);
  if (d < -0.999999f) return {1.0f, 0.0f, 0.0f, 0.0f};  // half a turn about x
  const glm::vec3 axis = glm::cross(from, to);
  const glm::vec4 q(axis.x, axis.y, axis.z, 1.0f + d);
  return q / glm::length(q);
}

// Linear RGB to 8-bit sRGB, the standard curve.
uint8_t srgb_byte(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  const float encoded = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(encoded * 255.0f));
}

std::vector<uint8_t> encode_png(const Texture& texture, const std::vector<uint8_t>& rgb) {
  std::vector<uint8_t> png;
  const int written = stbi_write_png_to_func(
      [](void* context, void* data, int size) {
        auto* bytes = static_cast<std::vector<uint8_t>*>(context);
        bytes->insert(bytes->end(), static_cast<uint8_t*>(data),
                      static_cast<uint8_t*>(data) + size);
      },
      &png, int(texture.width), int(texture.height), 3, rgb.data(), int(texture.width) * 3);
  if (!written) throw Error(BAKEGI_ERROR_INTERNAL, "a texture could not be encoded as PNG");
  return png;
}

std::vector<uint8_t> encode_srgb_png(const Texture& texture) {
  std::vector<uint8_t> rgb(size_t(texture.width) * texture.height * 3);
  for (size_t i = 0; i < texture.texel_count() && 3 * i + 2 < rgb.size(); ++i) {
    const glm::vec3 texel = texture.texel(i);
    rgb[3 * i] = srgb_byte(texel.x);
    rgb[3 * i + 1] = srgb_byte(texel.y);
    rgb[3 * i + 2] = srgb_byte(texel.z);
  }
  return encode_png(texture, rgb);
}

// A see-through material's opacity texture (its red channel x opacity) as linear grey, the
// page's alpha map (three.js reads an alpha map's green channel, unconverted).
std::vector<uint8_t> encode_opacity_png(const Texture& texture, float opacity) {
  std::vector<uint8_t> rgb(size_t(texture.width) * texture.height * 3);
  for (size_t i = 0; i < texture.texel_count() && 3 * i + 2 < rgb.size(); ++i) {
    const float value = std::clamp(texture.texel(i).x * opacity, 0.0f, 1.0f);
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = uint8_t(std::lround(value * 255.0f));
  }
  return encode_png(texture, rgb);
}

// The page's part of a see-through material (scene/scene.h): the share of light passing
// where the surface is (transmission), its opacity where there is no texture, and the alpha
// map's glTF texture; nothing for an opaque material.
std::string see_through_extras(const Material& material, int opacity_texture) {
  if (!material.lets_light_pass()) return "";
  std::string extras = ",\"see_through\":{\"opacity\":" + json_number(material.opacity) +
                       ",\"transmission\":" + json_number(material.transmission);
  if (opacity_texture >= 0) extras += ",\"opacity_texture\":" + std::to_string(opacity_texture);
  return extras + "}";
}

struct Primitive {
  uint32_t mesh = 0, material = 0;
  std::vector<uint32_t> triangles;  // of the mesh
};

bool casts_shadow(const Light& light) {
  return (light.flags & BAKEGI_LIGHT_NO_SHADOW) == 0;
}

// Cycles' Spread narrower than a Lambertian emitter's (0 and pi are both Lambertian: bakegi.h).
bool has_narrow_spread(const Light& light) {
  return light.type == BAKEGI_LIGHT_AREA && light.spot_size > 0.0f &&
         light.spot_size < std::numbers::pi_v<float> - 2e-4f;
}

// How the page draws the light its lamps do not carry, said on the page (its status line) and
// by Export for Web (its warnings): the world's and emitters' direct light needs visibility
// the page lacks, so it comes from the grid when the grid carries it (soft), else only its
// bounce reaches the page.
std::vector<std::string> lighting_notes(const SceneDescription& scene, bool from_grid,
                                        bool without_visibility) {
  std::vector<std::string> notes;
  if (without_visibility) {
    notes.push_back(
        "the grid is too large for a visibility volume: on the web page its light "
        "may pass through walls thinner than a cell");
  }
  if (std::max({scene.world_radiance.x, scene.world_radiance.y, scene.world_radiance.z}) > 0.0f) {
    notes.push_back(from_grid ? "the world (sky) lights this scene: on the web page its direct "
                                "light comes from the grid, soft and without sharp shadows"
                              : "the world (sky) lights this scene: the web page shows its light "
                                "once bounced (the grid), not its direct light");
  }
  if (std::any_of(scene.lights.begin(), scene.lights.end(), has_narrow_spread)) {
    notes.push_back(
        "an area light's Spread is under 180 degrees: the web page spreads its light over the "
        "whole hemisphere (brighter beside it than in Blender), as three.js' area lights do");
  }
  if (std::any_of(scene.materials.begin(), scene.materials.end(),
                  [](const Material& m) { return m.is_emissive(); })) {
    notes.push_back(from_grid ? "emissive surfaces light this scene: on the web page their direct "
                                "light comes from the grid, soft and without sharp shadows"
                              : "emissive surfaces glow on the web page but their direct light on "
                                "others is not drawn there, only its bounce (the grid)");
  }
  return notes;
}

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) s += ',';
    s += items[i];
  }
  return s;
}

}  // namespace

WebGltf encode_web_gltf(const SceneDescription& scene, const WebExportOptions& options) {
  WebGltf out;
  BufferBuilder buffer;
  std::vector<std::string> nodes, meshes, scene_nodes;

  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    std::map<uint32_t, Primitive> by_material;
    for (uint32_t t = 0; t < mesh.indices.size() / 3; ++t) {
      const uint32_t material =
          mesh.triangle_materials.empty() ? mesh.material : mesh.triangle_materials[t];
      Primitive& p = by_material[material];
      p.mesh = m, p.material = material;
      p.triangles.push_back(t);
    }
    std::vector<std::string> primitives;
    for (const auto& [material, primitive] : by_material) {
      // The primitive's own vertices, and whether its shading is flat. A textured one keeps
      // a vertex per (vertex, uv): its UV seams stay seams (and borders to the simplifier).
      const bool textured = material < scene.materials.size() &&
                            scene.materials[material].albedo_texture != BAKEGI_NO_TEXTURE &&
                            !mesh.corner_uvs.empty();
      const bool has_reach = m < options.corner_reads_grid.size() &&
                             options.corner_reads_grid[m].size() == mesh.indices.size();
      std::map<std::tuple<uint32_t, float, float, uint8_t>, uint32_t> local;
      std::vector<uint32_t> indices;
      std::vector<glm::vec3> positions, normal_sums;
      std::vector<glm::vec2> uvs;
      std::vector<float> reads_grid;
      bool flat = true;
      for (const uint32_t t : primitive.triangles) {
        glm::vec3 p[3];
        for (int c = 0; c < 3; ++c) {
          const uint32_t v = mesh.indices[3 * t + c];
          if (v >= mesh.positions.size()) {
            throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                        "mesh " + std::to_string(m) + " indexes past its vertices");
          }
          const glm::vec2 uv = textured ? mesh.corner_uvs[3 * t + c] : glm::vec2(0.0f);
          const uint8_t reads = has_reach ? options.corner_reads_grid[m][3 * t + c] : 1;
          const auto [at, added] =
              local.try_emplace({v, uv.x, uv.y, reads}, uint32_t(positions.size()));
          if (added) {
            positions.push_back(mesh.positions[v]);
            normal_sums.push_back(glm::vec3(0.0f));
            uvs.push_back(uv);
            reads_grid.push_back(reads ? 1.0f : 0.0f);
          }
          indices.push_back(at->second);
          p[c] = mesh.positions[v];
        }
        const glm::vec3 face = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float length = glm::length(face);
        for (int c = 0; c < 3; ++c) {
          const glm::vec3 n = mesh.corner_normals.empty() ? face : mesh.corner_normals[3 * t + c];
          normal_sums[indices[indices.size() - 3 + c]] += n;
          if (!mesh.corner_normals.empty() && length > 0.0f &&
              glm::dot(glm::normalize(n), face / length) < 0.999f) {
            flat = false;
          }
        }
      }
      const ProgressiveMesh pm = build_progressive_mesh(positions, indices);
      const size_t count = pm.original_vertex.size();
      std::vector<glm::vec3> streamed(count), normals(count);
      glm::vec3 lo(INFINITY), hi(-INFINITY);
      for (size_t v = 0; v < count; ++v) {
        streamed[v] = to_gltf(positions[pm.original_vertex[v]]);
        const glm::vec3 sum = to_gltf(normal_sums[pm.original_vertex[v]]);
        const float length = glm::length(sum);
        normals[v] = length > 0.0f ? sum / length : glm::vec3(0.0f, 1.0f, 0.0f);
        lo = glm::min(lo, streamed[v]);
        hi = glm::max(hi, streamed[v]);
      }
      if (pm.faces.empty()) continue;  // nothing but degenerate triangles
      const int position =
          buffer.add(streamed.data(), count * 12, count, kFloat, "VEC3", kArrayBuffer,
                     ",\"min\":" + vec3(lo) + ",\"max\":" + vec3(hi));
      std::string attributes = "\"POSITION\":" + std::to_string(position);
      if (!flat) {  // without NORMAL a glTF viewer shades flat, as the spec asks
        attributes += ",\"NORMAL\":" + std::to_string(buffer.add(normals.data(), count * 12, count,
                                                                 kFloat, "VEC3", kArrayBuffer));
      }
      if (textured) {
        // The core's textures have row 0 at v = 0 and are written top row first, so glTF's
        // v (0 at the image's top) is the core's v unchanged.
        std::vector<glm::vec2> streamed_uvs(count);
        for (size_t v = 0; v < count; ++v) streamed_uvs[v] = uvs[pm.original_vertex[v]];
        attributes +=
            ",\"TEXCOORD_0\":" + std::to_string(buffer.add(streamed_uvs.data(), count * 8, count,
                                                           kFloat, "VEC2", kArrayBuffer));
      }
      if (!options.corner_reads_grid.empty()) {
        std::vector<float> streamed_reads(count);
        for (size_t v = 0; v < count; ++v) streamed_reads[v] = reads_grid[pm.original_vertex[v]];
        attributes += ",\"_BAKEGI_READS_GRID\":" +
                      std::to_string(buffer.add(streamed_reads.data(), count * 4, count, kFloat,
                                                "SCALAR", kArrayBuffer));
      }
      const int faces = buffer.add(pm.faces.data(), pm.faces.size() * 4, pm.faces.size(),
                                   kUnsignedInt, "SCALAR", kElementArrayBuffer);
      const int parent = buffer.add(pm.parent.data(), count * 4, count, kUnsignedInt, "SCALAR", 0);
      const int valid_at = buffer.add(pm.valid_at.data(), pm.valid_at.size() * 4,
                                      pm.valid_at.size(), kUnsignedInt, "SCALAR", 0);
      std::string levels;
      for (const uint32_t n : pm.level_vertices) {
        if (!levels.empty()) levels += ',';
        levels += std::to_string(n);
      }
      primitives.push_back(
          "{\"attributes\":{" + attributes + "},\"indices\":" + std::to_string(faces) +
          ",\"material\":" + std::to_string(material) +
          ",\"mode\":4,\"extras\":{\"bakegi_progressive\":{\"parent\":" + std::to_string(parent) +
          ",\"valid_at\":" + std::to_string(valid_at) + ",\"level_vertices\":[" + levels + "]}}}");
      ++out.primitives;
      out.vertices += count;
      out.faces += pm.valid_at.size();
    }
    if (primitives.empty()) continue;
    meshes.push_back("{\"name\":" + json_quote("mesh " + std::to_string(m)) + ",\"primitives\":[" +
                     join(primitives) + "]}");
    scene_nodes.push_back(std::to_string(nodes.size()));
    nodes.push_back("{\"mesh\":" + std::to_string(meshes.size() - 1) +
                    ",\"extras\":{\"object_id\":" + std::to_string(mesh.object_id) + "}}");
  }

  // Albedo textures as PNG images (8-bit sRGB, as glTF's base colour textures are).
  std::vector<std::string> textures, images;
  std::map<uint32_t, size_t> texture_index;
  for (const Material& material : scene.materials) {
    const uint32_t t = material.albedo_texture;
    if (t == BAKEGI_NO_TEXTURE || t >= scene.textures.size() || texture_index.count(t)) continue;
    const std::string name = "texture_" + std::to_string(t) + ".png";
    out.images.push_back({name, encode_srgb_png(scene.textures[t])});
    texture_index[t] = textures.size();
    textures.push_back("{\"sampler\":0,\"source\":" + std::to_string(images.size()) + "}");
    images.push_back("{\"uri\":" + json_quote(name) + "}");
  }

  // See-through materials' opacity textures, one image per material (opacity x texture).
  std::map<size_t, size_t> opacity_index;  // material -> glTF texture
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    const uint32_t t = material.opacity_texture;
    if (t == BAKEGI_NO_TEXTURE || t >= scene.textures.size()) continue;
    const std::string name = "opacity_" + std::to_string(m) + ".png";
    out.images.push_back({name, encode_opacity_png(scene.textures[t], material.opacity)});
    opacity_index[m] = textures.size();
    textures.push_back("{\"sampler\":0,\"source\":" + std::to_string(images.size()) + "}");
    images.push_back("{\"uri\":" + json_quote(name) + "}");
  }

  std::vector<std::string> materials;
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& material = scene.materials[m];
    const glm::vec3 base = glm::clamp(material.albedo, 0.0f, 1.0f);
    const auto texture = texture_index.find(material.albedo_texture);
    const std::string base_texture =
        texture == texture_index.end()
            ? std::string()
            : ",\"baseColorTexture\":{\"index\":" + std::to_string(texture->second) + "}";
    const float peak = std::max({material.emission.x, material.emission.y, material.emission.z});
    const glm::vec3 emissive = peak > 0.0f ? material.emission / peak : glm::vec3(0.0f);
    materials.push_back(
        "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[" + json_number(base.x) + "," +
        json_number(base.y) + "," + json_number(base.z) + ",1]" + base_texture +
        ",\"metallicFactor\":0,\"roughnessFactor\":1},\"emissiveFactor\":" + vec3(emissive) +
        ",\"extras\":{\"emission_radiance\":" + vec3(material.emission) +
        see_through_extras(material, opacity_index.count(m) ? int(opacity_index[m]) : -1) + "}}");
  }

  std::vector<std::string> lights, area_lights;
  for (const Light& light : scene.lights) {
    const float peak = std::max({light.color.x, light.color.y, light.color.z});
    const glm::vec3 color = peak > 0.0f ? light.color / peak : glm::vec3(0.0f);
    std::string node = "{";
    if (light.type == BAKEGI_LIGHT_AREA) {
      area_lights.push_back(
          "{\"position\":" + vec3(to_gltf(light.position)) + ",\"direction\":" +
          vec3(to_gltf(light.direction)) + ",\"axis_u\":" + vec3(to_gltf(light.axis_u)) +
          ",\"size_x\":" + json_number(light.size_x) + ",\"size_y\":" +
          json_number(light.shape == BAKEGI_AREA_SQUARE || light.shape == BAKEGI_AREA_DISK
                          ? light.size_x
                          : light.size_y) +
          ",\"shape\":" + std::to_string(int(light.shape)) + ",\"radiance\":" + vec3(light.color) +
          ",\"spread\":" + json_number(light.spot_size) +
          ",\"cast_shadow\":" + (casts_shadow(light) ? "true" : "false") + "}");
      continue;
    }
    std::string description = "{\"color\":" + vec3(color) + ",\"intensity\":" + json_number(peak);
    // glTF's lights cast shadows (three.js' shadow maps on the page); Cast Shadow off says not.
    if (!casts_shadow(light)) description += ",\"extras\":{\"cast_shadow\":false}";
    if (light.type == BAKEGI_LIGHT_POINT) {
      description += ",\"type\":\"point\"}";
      node += "\"translation\":" + vec3(to_gltf(light.position));
    } else if (light.type == BAKEGI_LIGHT_SPOT) {
      const float outer = 0.5f * light.spot_size;
      description += ",\"type\":\"spot\",\"spot\":{\"innerConeAngle\":" +
                     json_number(outer * (1.0f - std::clamp(light.spot_blend, 0.0f, 1.0f))) +
                     ",\"outerConeAngle\":" + json_number(outer) + "}}";
      const glm::vec4 q = rotation_to(to_gltf(light.direction));
      node += "\"translation\":" + vec3(to_gltf(light.position)) + ",\"rotation\":" + vec(&q.x, 4);
    } else {
      description += ",\"type\":\"directional\"}";
      const glm::vec4 q = rotation_to(to_gltf(light.direction));
      node += "\"rotation\":" + vec(&q.x, 4);
    }
    lights.push_back(description);
    scene_nodes.push_back(std::to_string(nodes.size()));
    nodes.push_back(node + ",\"extensions\":{\"KHR_lights_punctual\":{\"light\":" +
                    std::to_string(lights.size() - 1) + "}}}");
  }

  std::string cameras;
  if (options.has_camera) {
    const WebCamera& c = options.camera;
    cameras =
        ",\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":" + json_number(c.yfov) +
        ",\"aspectRatio\":" + json_number(c.aspect) + ",\"znear\":0.01}}]";
    scene_nodes.push_back(std::to_string(nodes.size()));
    const glm::vec4 rotation = multiply(glm::vec4(-kHalfSqrt2, 0.0f, 0.0f, kHalfSqrt2), c.rotation);
    nodes.push_back("{\"camera\":0,\"translation\":" + vec3(to_gltf(c.position)) +
                    ",\"rotation\":" + vec(&rotation.x, 4) + "}");
  }

  std::ostringstream json;
  json << "{\"asset\":{\"version\":\"2.0\",\"generator\":"
       << json_quote(std::string("bakegi ") + bakegi_version_string() + " web export") << "}";
  if (!lights.empty()) {
    json << ",\"extensionsUsed\":[\"KHR_lights_punctual\"],\"extensions\":{"
         << "\"KHR_lights_punctual\":{\"lights\":[" << join(lights) << "]}}";
  }
  // glTF arrays, where present, hold at least one item.
  auto field = [](const char* name, const std::vector<std::string>& items) {
    return items.empty() ? std::string() : ",\"" + std::string(name) + "\":[" + join(items) + "]";
  };
  const std::string roots = field("nodes", scene_nodes);
  json << ",\"scene\":0,\"scenes\":[{" << (roots.empty() ? roots : roots.substr(1)) << "}]"
       << field("nodes", nodes) << field("meshes", meshes) << field("materials", materials)
       << cameras << field("textures", textures) << field("images", images)
       << (textures.empty() ? ""
                            : ",\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,"
                              "\"wrapS\":10497,\"wrapT\":10497}]")
       << field("accessors", buffer.accessors) << field("bufferViews", buffer.views);
  if (!buffer.bin.empty()) {
    json << ",\"buffers\":[{\"uri\":\"scene.bin\",\"byteLength\":" << buffer.bin.size() << "}]";
  }
  std::vector<std::string> quoted_notes;
  for (const std::string& note : lighting_notes(scene, options.grid_has_emitted_light,
                                                options.grid_too_large_for_visibility)) {
    quoted_notes.push_back(json_quote(note));
  }
  json << ",\"extras\":{\"bakegi\":{\"grid\":"
       << (options.grid_file.empty() ? std::string("null") : json_quote(options.grid_file))
       << ",\"grid_visibility\":"
       << (options.grid_visibility_file.empty() ? std::string("null")
                                                : json_quote(options.grid_visibility_file))
       << ",\"grid_has_emitted_light\":" << (options.grid_has_emitted_light ? "true" : "false")
       << ",\"notes\":[" << join(quoted_notes) << "],\"area_lights\":[" << join(area_lights)
       << "],\"world_radiance\":" << vec3(scene.world_radiance)
       << ",\"units\":\"radiance W/(m^2 sr); point and spot "
       << "intensity W/sr; sun irradiance W/m^2\"}}}";
  out.json = json.str();
  out.bin = std::move(buffer.bin);
  return out;
}

}  // namespace bakegi
