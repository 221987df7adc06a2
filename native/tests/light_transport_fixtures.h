// Scenes and a bake runner shared by the light-transport tests (direct light, path tracer).
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "lights/direct_light.h"
#include "scene/bake_points.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "scene/scene_validation.h"
#include "settings/settings.h"
#include "solvers/solver.h"
#include "util/job_context.h"

namespace bakegi::test {

inline uint32_t add_material(SceneDescription& d, glm::vec3 albedo, glm::vec3 emission = {},
                             bool two_sided = true) {
  Material m;
  m.albedo = albedo;
  m.emission = emission;
  m.emission_two_sided = two_sided;
  d.materials.push_back(m);
  return uint32_t(d.materials.size() - 1);
}

// A quad centred at `center` spanning center +- half_u * u +- half_v * v, as two triangles
// wound counter-clockwise around u x v (the face normal).
inline void add_quad(SceneDescription& d, glm::vec3 center, glm::vec3 u, glm::vec3 v, float half_u,
                     float half_v, uint32_t material) {
  Mesh mesh;
  mesh.positions = {center - u * half_u - v * half_v, center + u * half_u - v * half_v,
                    center + u * half_u + v * half_v, center - u * half_u + v * half_v};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  mesh.material = material;
  d.meshes.push_back(std::move(mesh));
}

// The room [-2, 2] x [-2, 2] x [0, 3] without its +x wall (where the tests cut a window or a
// hole): floor, ceiling and the other three walls, of `material`.
inline void add_room_without_plus_x_wall(SceneDescription& d, uint32_t material) {
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  add_quad(d, {0, 0, 0}, x, y, 2, 2, material);         // floor
  add_quad(d, {0, 0, 3}, y, x, 2, 2, material);         // ceiling
  add_quad(d, {-2, 0, 1.5f}, y, z, 2, 1.5f, material);  // -x wall
  add_quad(d, {0, -2, 1.5f}, z, x, 1.5f, 2, material);  // -y wall
  add_quad(d, {0, 2, 1.5f}, x, z, 2, 1.5f, material);   // +y wall
}

// add_quad with UVs: the quad's corner centre - half_u u - half_v v gets uv_lo and the
// opposite corner uv_hi, linear in between (so u runs along `u` and v along `v`).
inline void add_quad_with_uvs(SceneDescription& d, glm::vec3 center, glm::vec3 u, glm::vec3 v,
                              float half_u, float half_v, uint32_t material, glm::vec2 uv_lo,
                              glm::vec2 uv_hi) {
  add_quad(d, center, u, v, half_u, half_v, material);
  const glm::vec2 corner[4] = {uv_lo, {uv_hi.x, uv_lo.y}, uv_hi, {uv_lo.x, uv_hi.y}};
  for (uint32_t i : d.meshes.back().indices) d.meshes.back().corner_uvs.push_back(corner[i]);
}

// A width x height texture whose texel (i, j) (row j at v = (j + 0.5) / height) is
// texel(i, j); returns its index.
template <typename TexelOf>
uint32_t add_texture(SceneDescription& d, uint32_t width, uint32_t height, TexelOf texel) {
  Texture texture;
  texture.width = width;
  texture.height = height;
  std::vector<glm::vec3> texels;
  for (uint32_t j = 0; j < height; ++j) {
    for (uint32_t i = 0; i < width; ++i) texels.push_back(texel(i, j));
  }
  texture.set_texels(std::move(texels));
  d.textures.push_back(std::move(texture));
  return uint32_t(d.textures.size() - 1);
}

enum class Facing { kInward, kOutward };

// The cube [lo, hi] as 12 triangles facing inwards (a room) or outwards (a solid block).
inline Mesh make_cube(glm::vec3 lo, glm::vec3 hi, Facing facing, uint32_t material) {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  }
  // Each face as a quad, counter-clockwise seen from inside.
  const uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    if (facing == Facing::kInward) {
      mesh.indices.insert(mesh.indices.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
    } else {
      mesh.indices.insert(mesh.indices.end(), {f[0], f[2], f[1], f[0], f[3], f[2]});
    }
  }
  mesh.material = material;
  return mesh;
}

// An icosphere: the icosahedron subdivided `subdivisions` times, vertices projected onto
// the sphere; 20 * 4^subdivisions triangles wound counter-clockwise seen from outside.
inline Mesh make_icosphere(glm::vec3 center, float radius, int subdivisions, uint32_t material) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                              {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                              {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<std::array<uint32_t, 3>> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      const uint32_t index = uint32_t(v.size() - 1);
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& f : faces) {
      const uint32_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    faces = std::move(next);
  }
  Mesh mesh;
  for (const auto& p : v) mesh.positions.push_back(center + p * radius);
  for (const auto& f : faces) mesh.indices.insert(mesh.indices.end(), f.begin(), f.end());
  mesh.material = material;
  return mesh;
}

inline Light point_light(glm::vec3 position, glm::vec3 intensity, float radius = 0.0f) {
  Light l;
  l.type = BAKEGI_LIGHT_POINT;
  l.position = position;
  l.color = intensity;
  l.radius = radius;
  return l;
}

inline Light area_light(bakegi_area_shape shape, glm::vec3 position, glm::vec3 direction,
                        glm::vec3 axis_u, float size_x, float size_y, glm::vec3 radiance) {
  Light l;
  l.type = BAKEGI_LIGHT_AREA;
  l.shape = shape;
  l.position = position;
  l.direction = direction;
  l.axis_u = axis_u;
  l.size_x = size_x;
  l.size_y = size_y;
  l.color = radiance;
  return l;
}

inline BakePoints make_points(const std::vector<glm::vec3>& positions,
                              const std::vector<glm::vec3>& normals) {
  BakePoints p;
  p.positions = positions;
  for (const auto& n : normals) p.normals.push_back(glm::normalize(n));
  p.object_ids.assign(positions.size(), 0);
  return p;
}

struct BakeOptions {
  std::string method = "pathtrace";
  int64_t samples = 64;
  int64_t seed = 0;
  int64_t sample_offset = 0;
  int64_t max_bounces = 64;
};

// Runs a solver at the points the way a bake job does (scene, tracer, direct light, solve,
// evaluate), on the calling thread's task arena.
class Baker {
 public:
  explicit Baker(const SceneDescription& description)
      : scene_(build_scene(description)), tracer_(scene_), direct_(scene_, tracer_) {}

  std::vector<glm::vec3> bake(const BakePoints& points, const BakeOptions& options,
                              uint64_t* rays = nullptr) {
    Settings settings;
    settings.set("samples", options.samples);
    settings.set("seed", options.seed);
    settings.set("sample_offset", options.sample_offset);
    if (options.method == "pathtrace") settings.set("max_bounces", options.max_bounces);
    JobContext context;
    auto solver = make_solver(options.method);
    auto field = solver->solve(SolveInputs{scene_, tracer_, direct_, settings, &points}, context);
    std::vector<glm::vec3> out(points.size());
    field->evaluate(points, out, context);
    if (rays) *rays = context.report().count("rays");
    return out;
  }

  const Scene& scene() const { return scene_; }
  const DirectLight& direct() const { return direct_; }

 private:
  Scene scene_;
  RayTracer tracer_;
  DirectLight direct_;
};

// Total area of a mesh's triangles (m²), in double precision.
inline double mesh_area(const Mesh& mesh) {
  double area = 0.0;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return area;
}

inline double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / double(v.size());
}

inline double standard_deviation(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / double(v.size() - 1));
}

}  // namespace bakegi::test
