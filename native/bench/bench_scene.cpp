#include "bench_scene.h"

#include <cstdlib>

#include "api/light_desc.h"
#include "procedural_box.h"
#include "scene/scene_file.h"
#include "scene/scene_validation.h"
#include "util/error.h"

namespace bakegi::bench {
namespace {

void check(bakegi_status status, const char* what) {
  if (status != BAKEGI_OK) {
    throw Error(status, std::string(what) + ": " + bakegi_last_error());
  }
}

// Hands a description to the C API element by element, as the add-on does.
bakegi_scene* to_c_api(const SceneDescription& d) {
  bakegi_scene* scene = nullptr;
  check(bakegi_scene_create(&scene), "bakegi_scene_create");
  for (const Texture& t : d.textures) {
    uint32_t id = 0;
    const std::vector<glm::vec3> texels = t.texels();
    check(bakegi_scene_add_texture(scene, t.width, t.height, &texels[0].x, &id), "texture");
  }
  for (const Material& m : d.materials) {
    bakegi_material_desc desc{{m.albedo.x, m.albedo.y, m.albedo.z},
                              m.albedo_texture,
                              {m.emission.x, m.emission.y, m.emission.z},
                              m.emission_two_sided ? 1u : 0u};
    uint32_t id = 0;
    check(bakegi_scene_add_material(scene, &desc, &id), "material");
    if (m.emission_texture != BAKEGI_NO_TEXTURE) {
      check(bakegi_scene_set_material_emission_texture(scene, id, m.emission_texture),
            "emission texture");
    }
  }
  for (const Mesh& m : d.meshes) {
    bakegi_mesh_desc desc{};
    desc.positions = &m.positions[0].x;
    desc.vertex_count = uint32_t(m.positions.size());
    desc.indices = m.indices.data();
    desc.triangle_count = uint32_t(m.indices.size() / 3);
    desc.corner_normals = m.corner_normals.empty() ? nullptr : &m.corner_normals[0].x;
    desc.corner_uvs = m.corner_uvs.empty() ? nullptr : &m.corner_uvs[0].x;
    desc.triangle_materials = m.triangle_materials.empty() ? nullptr : m.triangle_materials.data();
    desc.material = m.material;
    desc.object_id = m.object_id;
    uint32_t id = 0;
    check(bakegi_scene_add_mesh(scene, &desc, &id), "mesh");
  }
  for (const Light& l : d.lights) {
    const bakegi_light_desc desc = to_light_desc(l);
    uint32_t id = 0;
    check(bakegi_scene_add_light(scene, &desc, &id), "light");
  }
  const float world[3] = {d.world_radiance.x, d.world_radiance.y, d.world_radiance.z};
  check(bakegi_scene_set_world(scene, world), "world");
  return scene;
}

BenchScene load() {
  BenchScene bench;
  SceneDescription description;
  const char* path = std::getenv("BAKEGI_BENCH_SCENE");
  if (path && *path) {
    SceneFile file = read_scene_file(path);
    description = std::move(file.scene);
    if (file.points) bench.points = std::move(*file.points);
    bench.name = path;
  } else {
    description = procedural_box();
    bench.name = "procedural Cornell box";
  }
  bench.scene = build_scene(description);
  if (bench.points.size() == 0) bench.points = triangle_centroid_points(bench.scene);
  bench.tracer = std::make_unique<RayTracer>(bench.scene);
  return bench;
}

}  // namespace

const BenchScene& bench_scene() {
  static const BenchScene scene = load();
  return scene;
}

const CApiScene& bench_scene_c_api() {
  static const CApiScene handles = [] {
    const BenchScene& bench = bench_scene();
    CApiScene c;
    c.scene = to_c_api(bench.scene.description);
    const BakePoints& p = bench.points;
    const bool has_ids = p.object_ids.size() == p.size();
    check(bakegi_points_create(&p.positions[0].x, &p.normals[0].x,
                               has_ids ? p.object_ids.data() : nullptr, p.size(), &c.points),
          "bake points");
    return c;  // lives as long as the program
  }();
  return handles;
}

}  // namespace bakegi::bench
