#include "grid/grid_gather.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "grid/grid_hit_radiance.h"
#include "lights/environment_light.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/owen_sobol.h"
#include "util/pcg32.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Rays per chunk: the hits of a chunk are held until their radiance is known (a few MB).
constexpr size_t kRaysPerChunk = size_t(1) << 17;

// Uniform on the hemisphere around +z: z = u1, azimuth 2 pi u2.
glm::vec3 uniform_hemisphere(float u1, float u2) {
  const float z = u1;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u2;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// I_delta of the light straight from the world (a ray along the unit `direction` that
// escapes: the world's image there, or its constant radiance) or from an emissive surface (a
// ray that meets its emitting side), += L * weighted direction, per channel.
void add_emitted(const Scene& scene, const glm::vec3& world, const Hit& hit,
                 const glm::vec3& direction, float weight, glm::mat3& out) {
  const glm::vec3 weighted_direction = direction * weight;
  glm::vec3 radiance = scene.environment ? scene.environment->radiance(direction) : world;
  if (hit.hit) {
    const Triangle& t = scene.triangles[hit.triangle];
    const Material& m = scene.material_of(t);
    if (!m.is_emissive()) return;
    if (!m.emission_two_sided && glm::dot(t.face_normal, weighted_direction) >= 0.0f) return;
    radiance = scene.emission_at(t, hit.b1, hit.b2);
  }
  for (int c = 0; c < 3; ++c) out[c] += radiance[c] * weighted_direction;
}

void check_options(const GridGatherOptions& options) {
  if (options.rays_per_hemisphere < 1 || options.rays_per_hemisphere > 65536) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "grid rays per hemisphere must be in [1, 65536], got " +
                    std::to_string(options.rays_per_hemisphere));
  }
  if (!(options.backface_fraction > 0.0f && options.backface_fraction <= 1.0f)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid backface fraction must be in (0, 1]");
  }
  if (!(options.ray_epsilon >= 0.0f) || !std::isfinite(options.ray_epsilon)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "grid ray epsilon must be finite and >= 0");
  }
}

}  // namespace

bool grid_gathers_emitted(const Scene& scene) {
  return max_component(scene.description.world_radiance) > 0.0f ||
         !scene.emissive_triangles.empty();
}

IrradianceVectorGrid gather_grid(const GridLayout& layout, const Scene& scene,
                                 const RayTracer& tracer, const HitRadiance& radiance,
                                 const GridGatherOptions& options, JobContext& context,
                                 GridGatherStatistics& statistics) {
  check_options(options);
  IrradianceVectorGrid grid(layout);
  const glm::vec3 world = scene.description.world_radiance;
  const bool gather_emitted = grid_gathers_emitted(scene);
  if (gather_emitted) grid.emitted.assign(grid.vectors.size(), glm::mat3(0.0f));
  const uint32_t rays = options.rays_per_hemisphere;
  const size_t rays_per_vertex = size_t(kGridHemispheres) * rays;
  const size_t vertices = layout.vertex_count();
  const size_t chunk_vertices = std::max<size_t>(1, kRaysPerChunk / rays_per_vertex);
  const float weight = 2.0f * kPi / float(rays);
  std::vector<Hit> first_hits;
  std::vector<glm::vec3> directions;
  std::vector<GridRayHit> hits;
  std::vector<uint32_t> hit_slot;
  std::vector<glm::vec3> hit_radiance;
  std::atomic<uint64_t> traced{0};

  for (size_t chunk_begin = 0; chunk_begin < vertices; chunk_begin += chunk_vertices) {
    context.throw_if_cancelled();
    const size_t chunk_end = std::min(vertices, chunk_begin + chunk_vertices);
    const size_t chunk_rays = (chunk_end - chunk_begin) * rays_per_vertex;
    first_hits.assign(chunk_rays, Hit{});
    directions.assign(chunk_rays, glm::vec3(0.0f));

    // Trace every vertex's rays; decide which vertices lie inside geometry.
    tbb::parallel_for(
        tbb::blocked_range<size_t>(chunk_begin, chunk_end, 4),
        [&](const tbb::blocked_range<size_t>& block) {
          context.throw_if_cancelled();
          for (size_t v = block.begin(); v != block.end(); ++v) {
            const glm::vec3 origin = layout.vertex_position(v);
            size_t backfaces = 0;
            for (int h = 0; h < kGridHemispheres; ++h) {
              const Frame frame(hemisphere_axis(h));
              const OwenSobolSeeds seeds =
                  sobol_seeds(options.seed, v * kGridHemispheres + h, 0, 0);
              for (uint32_t r = 0; r < rays; ++r) {
                const SobolPoint p = owen_sobol_point(r, seeds);
                const glm::vec3 w =
                    frame.to_world(uniform_hemisphere(unit_float(p.x), unit_float(p.y)));
                const size_t slot = (v - chunk_begin) * rays_per_vertex + size_t(h) * rays + r;
                directions[slot] = w;
                first_hits[slot] = tracer.intersect(Ray{origin, w, options.ray_epsilon, 1e30f});
                const Hit& hit = first_hits[slot];
                if (hit.hit && glm::dot(w, scene.triangles[hit.triangle].face_normal) > 0.0f) {
                  ++backfaces;
                }
              }
            }
            grid.valid[v] = float(backfaces) < options.backface_fraction * float(rays_per_vertex);
          }
          traced.fetch_add((block.end() - block.begin()) * rays_per_vertex,
                           std::memory_order_relaxed);
        });

    // The radiance at the hits of valid vertices.
    hits.clear();
    hit_slot.clear();
    for (size_t slot = 0; slot < chunk_rays; ++slot) {
      const size_t v = chunk_begin + slot / rays_per_vertex;
      if (!grid.valid[v]) continue;
      if (gather_emitted)
        add_emitted(scene, world, first_hits[slot], directions[slot], weight,
                    grid.emitted_at(v, int((slot % rays_per_vertex) / rays)));
      if (!first_hits[slot].hit) continue;
      hits.push_back({directions[slot], first_hits[slot],
                      uint64_t(v) * rays_per_vertex + (slot % rays_per_vertex)});
      hit_slot.push_back(uint32_t(slot));
    }
    hit_radiance.assign(hits.size(), glm::vec3(0.0f));
    uint64_t radiance_rays = 0;
    {
      ProgressRange range(context, double(chunk_begin) / double(vertices),
                          double(chunk_end) / double(vertices));
      radiance.evaluate(hits, hit_radiance, options.seed, context, radiance_rays);
    }
    traced.fetch_add(radiance_rays, std::memory_order_relaxed);

    // I_delta += 2 pi / N * L w, per channel.
    for (size_t n = 0; n < hits.size(); ++n) {
      const size_t slot = hit_slot[n];
      const size_t v = chunk_begin + slot / rays_per_vertex;
      const int h = int((slot % rays_per_vertex) / rays);
      glm::mat3& m = grid.at(v, h);
      const glm::vec3 w = directions[slot] * weight;
      for (int c = 0; c < 3; ++c) m[c] += hit_radiance[n][c] * w;
    }
    context.set_stage_progress(double(chunk_end) / double(vertices));
  }
  statistics.rays = traced.load();
  statistics.invalid_vertices =
      uint64_t(std::count(grid.valid.begin(), grid.valid.end(), uint8_t(0)));
  return grid;
}

}  // namespace bakegi
