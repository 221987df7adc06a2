#include "solvers/antiradiance/back_sides.h"

#include "solvers/antiradiance/coincident_faces.h"

#include <cmath>
#include <numbers>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace bakegi::antiradiance {
namespace {

// Rays leave this far off the surface (relative to the scene's extent), past float noise.
constexpr float kRelativeOffset = 1e-5f;
// Where on the triangle the rays start (barycentrics b1, b2): the centroid and a point
// towards each corner, so a large triangle is not judged by its centre alone.
constexpr float kStartPoints[4][2] = {{1.0f / 3.0f, 1.0f / 3.0f},
                                      {1.0f / 6.0f, 1.0f / 6.0f},
                                      {2.0f / 3.0f, 1.0f / 6.0f},
                                      {1.0f / 6.0f, 2.0f / 3.0f}};

// Unit vectors t, b with (t, b, n) orthonormal.
void frame(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  t = glm::normalize(glm::cross(helper, n));
  b = glm::cross(n, t);
}

// Ray i of kExposureRays, cosine-distributed about n: stratified in cos²θ, golden-ratio
// steps in azimuth.
glm::vec3 exposure_direction(int i, const glm::vec3& n, const glm::vec3& t, const glm::vec3& b) {
  const float u1 = (float(i) + 0.5f) / float(kExposureRays);
  const float u2 = std::fmod(float(i) * 0.6180339887f, 1.0f);
  const float r = std::sqrt(u1);
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  return r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1.0f - u1) * n;
}

bool is_positive(const glm::vec3& v) {
  return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f;
}

}  // namespace

bool on_open_mesh(const Scene& scene, const Triangle& t) {
  return t.mesh < scene.mesh_topology.size() && scene.mesh_topology[t.mesh].open();
}

std::vector<std::string> open_mesh_warnings(const Scene& scene, bool back_sides_made) {
  std::string open_list, flipped_list;
  size_t open_count = 0, flipped_count = 0;
  auto name = [&](size_t m) {
    return "mesh " + std::to_string(m) + " (object " +
           std::to_string(scene.description.meshes[m].object_id) + ")";
  };
  for (size_t m = 0; m < scene.mesh_topology.size(); ++m) {
    const MeshTopology& topology = scene.mesh_topology[m];
    std::string& list = topology.open() ? open_list : flipped_list;
    size_t& count = topology.open() ? open_count : flipped_count;
    if (!topology.open() && topology.inconsistent_edges == 0) continue;
    if (count < kMaxNamedMeshes) {
      list += (list.empty() ? "" : "; ") + name(m) + ": " + describe_topology_problems(topology);
    }
    ++count;
  }
  auto more = [](size_t count) {
    return count > kMaxNamedMeshes
               ? "; and " + std::to_string(count - kMaxNamedMeshes) + " more meshes"
               : std::string();
  };
  std::vector<std::string> warnings;
  if (open_count > 0 && back_sides_made) {
    warnings.push_back(std::to_string(open_count) + " meshes do not bound a solid (" + open_list +
                       more(open_count) +
                       "); the method assumes closed solids, so where the back of such a "
                       "surface faces open space it gets a back side of its own (closing the "
                       "mesh or giving a plane thickness is more accurate)");
  }
  if (flipped_count > 0) {
    warnings.push_back(std::to_string(flipped_count) +
                       " closed meshes have faces wound against "
                       "their neighbours (" +
                       flipped_list + more(flipped_count) +
                       "); the method takes a face's normal side as the outside, so light at "
                       "flipped faces is wrong (recalculate normals)");
  }
  return warnings;
}

std::vector<uint8_t> exposed_back_sides(const Scene& scene, const RayTracer& tracer) {
  std::vector<uint8_t> exposed(scene.triangles.size(), 0);
  const float offset = kRelativeOffset * std::max(scene.extent(), 1e-3f);
  const bool lit_world = is_positive(scene.description.world_radiance);
  // A face modelled back to back with another already has its back side.
  const std::vector<uint8_t> backed = backed_by_coincident_face(scene);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, scene.triangles.size(), 64),
      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          const Triangle& tri = scene.triangles[i];
          if (!on_open_mesh(scene, tri) || backed[i]) continue;
          const glm::vec3 back = -tri.face_normal;
          glm::vec3 t, b;
          frame(back, t, b);
          int open = 0;
          for (int r = 0; r < kExposureRays; ++r) {
            const float* start = kStartPoints[r % 4];
            const glm::vec3 p =
                (1.0f - start[0] - start[1]) * tri.p[0] + start[0] * tri.p[1] + start[1] * tri.p[2];
            Ray ray;
            ray.origin = p + offset * back;
            ray.direction = exposure_direction(r, back, t, b);
            const Hit hit = tracer.intersect(ray);
            if (!hit.hit) {
              open += lit_world ? 1 : 0;
              continue;
            }
            const glm::vec3 hit_normal = scene.triangles[hit.triangle].face_normal;
            if (glm::dot(ray.direction, hit_normal) >= 0.0f) continue;  // a back face: inside
            // A front face: open space unless its own mirrored view ends on a back face.
            Ray mirrored;
            mirrored.direction =
                ray.direction - 2.0f * glm::dot(ray.direction, hit_normal) * hit_normal;
            mirrored.origin = ray.origin + hit.t * ray.direction + offset * hit_normal;
            const Hit second = tracer.intersect(mirrored);
            if (!second.hit ||
                glm::dot(mirrored.direction, scene.triangles[second.triangle].face_normal) < 0.0f) {
              ++open;
            }
          }
          exposed[i] = float(open) >= kMinOpenFraction * float(kExposureRays) ? 1 : 0;
        }
      });
  return exposed;
}

}  // namespace bakegi::antiradiance
