#include "solvers/meshless/sky_visibility.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/ray_tracer.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::meshless {

std::vector<float> sky_visibility(const BasisHierarchy& points, const RayTracer& tracer,
                                  const SkyVisibilitySettings& settings, JobContext& context,
                                  uint64_t& rays_cast) {
  std::vector<float> visibility(points.size(), 0.0f);
  const uint32_t side =
      std::max(1u, static_cast<uint32_t>(std::sqrt(static_cast<double>(settings.rays))));
  const uint32_t rays = side * side;
  std::atomic<uint64_t> total{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, points.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
        if (context.is_cancelled()) return;
        uint64_t local = 0;
        for (size_t i = r.begin(); i != r.end(); ++i) {
          const BasisPoint& p = points.point(static_cast<uint32_t>(i));
          const Frame frame(p.normal);
          const glm::vec3 origin = p.position + p.normal * settings.ray_epsilon;
          RandomStream rng = sample_stream(settings.seed, i, 0);
          uint32_t open = 0;
          for (uint32_t k = 0; k < rays; ++k) {
            const float u1 = (static_cast<float>(k % side) + rng.next_float()) / side;
            const float u2 = (static_cast<float>(k / side) + rng.next_float()) / side;
            const glm::vec3 direction = frame.to_world(sample_cosine_hemisphere(u1, u2));
            open += tracer.occluded(Ray{origin, direction, 0.0f, 1e30f}) ? 0 : 1;
          }
          local += rays;
          visibility[i] = static_cast<float>(open) / static_cast<float>(rays);
        }
        total += local;
      });
  context.throw_if_cancelled();
  rays_cast += total.load();
  return visibility;
}

}  // namespace bakegi::meshless
