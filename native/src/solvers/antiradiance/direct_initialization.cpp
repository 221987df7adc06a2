#include "solvers/antiradiance/direct_initialization.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "direct/surface_point.h"
#include "solvers/antiradiance/push_pull.h"
#include "util/error.h"
#include "util/random.h"

namespace bakegi::antiradiance {

namespace {

constexpr size_t kPatchesPerBlock = 64;
// Patches per shadow-ray block: small, since each costs `samples` ray queries.
constexpr size_t kPatchesPerTracingBlock = 16;

}  // namespace

void initialize_direct(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                       std::span<const glm::vec3> direct_irradiance, RadianceTables& tables) {
  if (tables.element_count() != hierarchy.element_count() ||
      tables.patch_count() != hierarchy.patch_count() || tables.bin_count() != bins.bin_count() ||
      direct_irradiance.size() != hierarchy.patch_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "direct initialization: sizes do not match the hierarchy");
  }
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  const int m = bins.bin_count();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        const Patch& patch = patches[p];
                        const glm::vec3 radiance =
                            patch.albedo * std::numbers::inv_pi_v<float> * direct_irradiance[p] +
                            patch.emission;
                        const glm::vec3 intensity = elements[patch.element].area * radiance;
                        const std::span<glm::vec3> exitant = tables.exitant(patch.element);
                        for (int j = 0; j < m; ++j) {
                          const float cosine = glm::dot(patch.normal, bins.direction(j));
                          exitant[size_t(j)] = std::max(cosine, 0.0f) * intensity;
                        }
                      }
                    });
  const std::span<glm::vec3> accumulated = tables.accumulated_irradiance();
  std::fill(accumulated.begin(), accumulated.end(), glm::vec3(0.0f));
  pull(hierarchy, tables);
}

std::vector<glm::vec3> direct_irradiance_at_patches(const ElementHierarchy& hierarchy,
                                                    const DirectLight& direct, int64_t samples,
                                                    uint64_t seed, JobContext& context) {
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  std::vector<glm::vec3> irradiance(patches.size(), glm::vec3(0.0f));
  if (samples <= 0) return irradiance;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerTracingBlock),
      [&](const tbb::blocked_range<size_t>& block) {
        uint64_t rays = 0;
        for (size_t p = block.begin(); p != block.end(); ++p) {
          context.throw_if_cancelled();
          const Patch& patch = patches[p];
          const SurfacePoint x{elements[patch.element].center, patch.shading_normal, patch.normal};
          glm::dvec3 sum(0.0);
          for (int64_t s = 0; s < samples; ++s) {
            Pcg32 rng = sample_stream(seed, p, uint64_t(s));
            const glm::vec3 value = direct.irradiance_sample(x, rng, rays);
            // A non-finite sample would poison the patch and everything it lights.
            if (std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z)) {
              sum += glm::dvec3(value);
            }
          }
          irradiance[p] = glm::vec3(sum / double(samples));
        }
        context.report().add_count("rays", rays);
      });
  return irradiance;
}

}  // namespace bakegi::antiradiance
