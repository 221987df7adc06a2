#include "procedural_box.h"

#include <cmath>

namespace bakegi::bench {
namespace {

// Published diffuse reflectances of the Cornell box.
constexpr glm::vec3 kRed{0.63f, 0.065f, 0.05f};
constexpr glm::vec3 kGreen{0.14f, 0.45f, 0.091f};
constexpr glm::vec3 kWhite{0.725f, 0.71f, 0.68f};

// Appends a grid of quads spanning origin + s*u + t*v, s, t in [0,1], two triangles per
// quad, wound so that u x v is the front.
void add_grid(Mesh& mesh, glm::vec3 origin, glm::vec3 u, glm::vec3 v, int cells_u, int cells_v) {
  const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
  for (int j = 0; j <= cells_v; ++j) {
    for (int i = 0; i <= cells_u; ++i) {
      mesh.positions.push_back(origin + u * (float(i) / cells_u) + v * (float(j) / cells_v));
    }
  }
  const auto at = [&](int i, int j) { return base + uint32_t(j * (cells_u + 1) + i); };
  for (int j = 0; j < cells_v; ++j) {
    for (int i = 0; i < cells_u; ++i) {
      mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
}

int cells_for(float length, int cells) {
  return std::max(1, int(std::lround(length / 2.0f * cells)));
}

Mesh wall(glm::vec3 origin, glm::vec3 u, glm::vec3 v, uint32_t material, int cells,
          uint32_t object_id) {
  Mesh mesh;
  add_grid(mesh, origin, u, v, cells, cells);
  mesh.material = material;
  mesh.object_id = object_id;
  return mesh;
}

// A closed-bottom-less box (top and four sides) of side 0.6 m, rotated about z.
Mesh box(float cx, float cy, float height, float degrees, uint32_t material, int cells,
         uint32_t object_id) {
  const float h = 0.3f;
  const int side = cells_for(0.6f, cells), up = cells_for(height, cells);
  Mesh mesh;
  add_grid(mesh, {-h, -h, height}, {0.6f, 0, 0}, {0, 0.6f, 0}, side, side);
  const glm::vec3 vertical{0, 0, height};
  add_grid(mesh, {-h, -h, 0}, {0.6f, 0, 0}, vertical, side, up);
  add_grid(mesh, {h, -h, 0}, {0, 0.6f, 0}, vertical, side, up);
  add_grid(mesh, {h, h, 0}, {-0.6f, 0, 0}, vertical, side, up);
  add_grid(mesh, {-h, h, 0}, {0, -0.6f, 0}, vertical, side, up);
  const float a = degrees * 3.14159265f / 180.0f;
  for (glm::vec3& p : mesh.positions) {
    p = {cx + std::cos(a) * p.x - std::sin(a) * p.y, cy + std::sin(a) * p.x + std::cos(a) * p.y,
         p.z};
  }
  mesh.material = material;
  mesh.object_id = object_id;
  return mesh;
}

}  // namespace

SceneDescription procedural_box(int cells) {
  SceneDescription scene;
  scene.materials = {Material{kRed}, Material{kGreen}, Material{kWhite}};
  const uint32_t red = 0, green = 1, white = 2;
  scene.meshes.push_back(wall({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, white, cells, 0));  // floor
  scene.meshes.push_back(wall({-1, -1, 2}, {0, 2, 0}, {2, 0, 0}, white, cells, 1));  // ceiling
  scene.meshes.push_back(wall({-1, 1, 0}, {2, 0, 0}, {0, 0, 2}, white, cells, 2));   // back
  scene.meshes.push_back(wall({-1, -1, 0}, {0, 2, 0}, {0, 0, 2}, red, cells, 3));    // left
  scene.meshes.push_back(wall({1, -1, 0}, {0, 0, 2}, {0, 2, 0}, green, cells, 4));   // right
  scene.meshes.push_back(box(0.3275f, -0.3725f, 0.6f, -16.6f, white, cells, 5));
  scene.meshes.push_back(box(-0.335f, 0.29f, 1.2f, 17.5f, white, cells, 6));

  // The classic emitter: a 0.47 m x 0.38 m rectangle 2 cm below the ceiling, facing down,
  // radiance (17, 12, 4) W/(m^2 sr).
  Light light;
  light.type = BAKEGI_LIGHT_AREA;
  light.position = {0, 0, 1.98f};
  light.direction = {0, 0, -1};
  light.axis_u = {1, 0, 0};
  light.color = {17, 12, 4};
  light.shape = BAKEGI_AREA_RECTANGLE;
  light.size_x = 0.47f;
  light.size_y = 0.38f;
  scene.lights.push_back(light);
  return scene;
}

BakePoints triangle_centroid_points(const Scene& scene) {
  BakePoints points;
  for (const Triangle& t : scene.triangles) {
    points.positions.push_back((t.p[0] + t.p[1] + t.p[2]) / 3.0f);
    points.normals.push_back(t.face_normal);
    points.object_ids.push_back(scene.description.meshes[t.mesh].object_id);
  }
  return points;
}

}  // namespace bakegi::bench
