#include "lightmap/backface_rejection.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"
#include "util/sampling.h"

namespace bakegi {

std::vector<uint8_t> flag_samples_inside_geometry(const Scene& scene, const RayTracer& tracer,
                                                  const std::vector<glm::vec3>& positions,
                                                  const std::vector<glm::vec3>& geometric_normals,
                                                  const std::vector<glm::vec3>& shading_normals,
                                                  const BackfaceRejectionOptions& options,
                                                  const CancelFlag* cancel) {
  if (options.rays == 0 || options.rays > 4096) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "backface rejection rays " + std::to_string(options.rays) + " not in 1..4096");
  }
  if (!(options.backface_fraction > 0 && options.backface_fraction <= 1)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "backface fraction must be in (0, 1]");
  }
  if (!(options.max_distance >= 0) || !std::isfinite(options.max_distance)) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "backface max distance must be finite and >= 0");
  }
  if (geometric_normals.size() != positions.size() || shading_normals.size() != positions.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "flag_samples_inside_geometry: array sizes differ");
  }
  // Stratified directions, the same for every sample: a sqrt(rays)-ish grid on the unit
  // square mapped to the cosine hemisphere (rows x columns >= rays, cells taken in order).
  const uint32_t columns = uint32_t(std::ceil(std::sqrt(double(options.rays))));
  const uint32_t rows = (options.rays + columns - 1) / columns;
  std::vector<glm::vec3> local(options.rays);
  for (uint32_t i = 0; i < options.rays; ++i) {
    local[i] = sample_cosine_hemisphere((float(i % columns) + 0.5f) / float(columns),
                                        (float(i / columns) + 0.5f) / float(rows));
  }
  // Rays leave a little above the surface so they do not hit their own triangle.
  const float offset = 1e-5f * std::max(scene.extent(), 1e-3f);
  const float tfar = options.max_distance > 0 ? options.max_distance : 1e30f;
  const uint32_t threshold =
      std::max(1u, uint32_t(std::ceil(double(options.backface_fraction) * options.rays - 1e-9)));

  std::vector<uint8_t> flags(positions.size(), 0);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, positions.size(), 64),
      [&](const tbb::blocked_range<size_t>& range) {
        throw_if_cancelled(cancel, "rejecting texels inside geometry");
        for (size_t i = range.begin(); i != range.end(); ++i) {
          glm::vec3 normal = geometric_normals[i];
          if (glm::dot(normal, shading_normals[i]) < 0) normal = -normal;
          const Frame frame(normal);
          uint32_t back_hits = 0;
          for (uint32_t r = 0; r < options.rays; ++r) {
            Ray ray;
            ray.origin = positions[i] + offset * normal;
            ray.direction = frame.to_world(local[r]);
            ray.tfar = tfar;
            const Hit hit = tracer.intersect(ray);
            if (hit.hit && glm::dot(ray.direction, scene.triangles[hit.triangle].face_normal) > 0) {
              ++back_hits;
            }
            // Decided either way: stop early.
            if (back_hits >= threshold) break;
            if (back_hits + (options.rays - 1 - r) < threshold) break;
          }
          flags[i] = back_hits >= threshold ? 1 : 0;
        }
      });
  return flags;
}

}  // namespace bakegi
