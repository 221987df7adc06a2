#include "grid/grid_hit_radiance.h"

#include <atomic>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "field/indirect_field.h"
#include "lights/direct_light.h"
#include "lights/surface_point.h"
#include "scene/bake_points.h"
#include "solvers/pathtrace/indirect_path.h"
#include "solvers/pathtrace/path_trace_solver.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

constexpr size_t kHitsPerBlock = 256;

// A non-finite sample would poison a whole vertex's sum; it counts as dark instead.
glm::vec3 finite_or_zero(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) ? v : glm::vec3(0.0f);
}

// Runs trace(i, rays) for every hit in parallel blocks, honouring cancel; adds the rays
// traced to `rays`.
template <typename Trace>
void for_each_hit(size_t count, JobContext& context, uint64_t& rays, Trace trace) {
  std::atomic<uint64_t> traced{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kHitsPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      context.throw_if_cancelled();
                      uint64_t block_rays = 0;
                      for (size_t i = block.begin(); i != block.end(); ++i) trace(i, block_rays);
                      traced.fetch_add(block_rays, std::memory_order_relaxed);
                    });
  rays += traced.load();
}

class PathTracedHitRadiance : public HitRadiance {
 public:
  PathTracedHitRadiance(const DirectLight& direct, int max_bounces)
      : direct_(direct), max_bounces_(max_bounces) {}

  void evaluate(std::span<const GridRayHit> hits, std::span<glm::vec3> out, uint64_t seed,
                JobContext& context, uint64_t& rays) const override {
    for_each_hit(hits.size(), context, rays, [&](size_t i, uint64_t& traced) {
      RandomStream rng = sample_stream(seed, hits[i].key, 0);
      const PathRadiance path =
          trace_from_first_hit(direct_, hits[i].hit, hits[i].direction, rng, max_bounces_, traced);
      out[i] = finite_or_zero(path.first_light + path.rest);
    });
  }

 private:
  const DirectLight& direct_;
  int max_bounces_;
};

class FieldHitRadiance : public HitRadiance {
 public:
  FieldHitRadiance(const DirectLight& direct, const IndirectField& field)
      : direct_(direct), field_(field) {}

  void evaluate(std::span<const GridRayHit> hits, std::span<glm::vec3> out, uint64_t seed,
                JobContext& context, uint64_t& rays) const override {
    const Scene& scene = direct_.scene();
    BakePoints points;
    points.positions.resize(hits.size());
    points.normals.resize(hits.size());
    points.object_ids.resize(hits.size());
    std::vector<glm::vec3> direct_light(hits.size());
    for_each_hit(hits.size(), context, rays, [&](size_t i, uint64_t& traced) {
      const Hit& hit = hits[i].hit;
      const SurfacePoint x = surface_at_hit(scene, hit, hits[i].direction);
      const Triangle& triangle = scene.triangles[hit.triangle];
      points.positions[i] = x.position;
      points.normals[i] = x.shading_normal;
      points.object_ids[i] = scene.description.meshes[triangle.mesh].object_id;
      RandomStream rng = sample_stream(seed, hits[i].key, 0);
      direct_light[i] = direct_.irradiance_sample(x, rng, traced);
    });
    std::vector<glm::vec3> indirect(hits.size(), glm::vec3(0.0f));
    field_.evaluate(points, indirect, context);
    for (size_t i = 0; i < hits.size(); ++i) {
      const Triangle& triangle = scene.triangles[hits[i].hit.triangle];
      const glm::vec3 albedo = scene.albedo_at(triangle, hits[i].hit.b1, hits[i].hit.b2);
      out[i] = finite_or_zero(albedo * (kInvPi * direct_light[i] + indirect[i]));
    }
  }

 private:
  const DirectLight& direct_;
  const IndirectField& field_;
};

}  // namespace

std::unique_ptr<HitRadiance> make_hit_radiance(const DirectLight& direct,
                                               const IndirectField& field) {
  if (const auto* paths = dynamic_cast<const PathTracedField*>(&field)) {
    return std::make_unique<PathTracedHitRadiance>(paths->direct(), paths->settings().max_bounces);
  }
  return std::make_unique<FieldHitRadiance>(direct, field);
}

}  // namespace bakegi
