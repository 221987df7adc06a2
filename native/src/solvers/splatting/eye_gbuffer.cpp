#include "solvers/splatting/eye_gbuffer.h"

#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "lights/surface_point.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

EyeGBuffer trace_eye_gbuffer(const Scene& scene, const RayTracer& tracer,
                             const PreviewCamera& camera, uint32_t width, uint32_t height) {
  EyeGBuffer g;
  g.width = width;
  g.height = height;
  const size_t n = g.size();
  g.hit.assign(n, 0);
  g.depth.assign(n, std::numeric_limits<float>::infinity());
  g.position.assign(n, glm::vec3(0.0f));
  g.normal.assign(n, glm::vec3(0.0f));
  g.geometric.assign(n, glm::vec3(0.0f));
  g.albedo.assign(n, glm::vec3(0.0f));
  g.glossy.assign(n, glm::vec3(0.0f));
  g.glossy_exponent.assign(n, 0.0f);
  g.emission.assign(n, glm::vec3(0.0f));
  g.view.assign(n, glm::vec3(0.0f));

  const glm::vec3 forward = glm::normalize(camera.forward);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float larger = float(std::max(width, height));
  // Half-extents of the image plane at unit distance (perspective) or in metres (ortho).
  const bool ortho = camera.ortho_scale > 0.0f;
  const float half_larger =
      ortho ? 0.5f * camera.ortho_scale : std::tan(0.5f * camera.fov_y) * larger / float(height);
  const float pixel = 2.0f * half_larger / larger;
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, 4), [&](const auto& rows) {
    for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const float u = (float(x) + 0.5f - 0.5f * width) * pixel + camera.shift_x * 2 * half_larger;
        const float v =
            (0.5f * height - float(y) - 0.5f) * pixel + camera.shift_y * 2 * half_larger;
        Ray ray;
        if (ortho) {
          ray.origin = camera.position + right * u + up * v;
          ray.direction = forward;
        } else {
          ray.origin = camera.position;
          ray.direction = glm::normalize(forward + right * u + up * v);
        }
        const Hit hit = tracer.intersect(ray);
        if (!hit.hit) continue;
        const size_t i = g.index(x, y);
        const Triangle& triangle = scene.triangles[hit.triangle];
        const SurfacePoint s = surface_at_hit(scene, hit, ray.direction);
        g.hit[i] = 1;
        g.position[i] = s.position;
        g.depth[i] = glm::dot(s.position - camera.position, forward);
        g.normal[i] = s.shading_normal;
        g.geometric[i] = s.geometric_normal;
        g.albedo[i] = scene.albedo_at(triangle, hit.b1, hit.b2);
        g.view[i] = -ray.direction;
        const Material& material = scene.material_of(triangle);
        if (material.has_glossy()) {
          g.glossy[i] = material.glossy;
          g.glossy_exponent[i] = material.glossy_exponent;
        }
        if (material.is_emissive() &&
            (material.emission_two_sided || glm::dot(triangle.face_normal, ray.direction) < 0)) {
          g.emission[i] = scene.emission_at(triangle, hit.b1, hit.b2);
        }
      }
    }
  });
  return g;
}

std::vector<glm::vec3> eye_direct_light(const EyeGBuffer& g, const DirectLight& direct,
                                        uint32_t samples, uint64_t seed) {
  std::vector<glm::vec3> out(g.size(), glm::vec3(0.0f));
  if (samples == 0) return out;
  // Without a world only lamps and emitters light: light sampling alone finds them all with
  // one ray each instead of two.
  const bool world = max_component(direct.world_radiance()) > 0.0f;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, g.size(), 1024), [&](const auto& range) {
    uint64_t rays = 0;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      if (!g.hit[i]) continue;
      const SurfacePoint x{g.position[i], g.normal[i], g.geometric[i]};
      glm::vec3 sum(0.0f);
      for (uint32_t s = 0; s < samples; ++s) {
        RandomStream rng(sample_pcg(seed, i, s));
        sum +=
            world ? direct.irradiance_sample(x, rng, rays) : direct.lamp_irradiance(x, rng, rays);
      }
      out[i] = sum * (kInvPi / float(samples));
    }
  });
  return out;
}

}  // namespace bakegi
