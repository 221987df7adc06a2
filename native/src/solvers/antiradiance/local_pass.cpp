#include "solvers/antiradiance/local_pass.h"

#include <numbers>
#include <span>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace bakegi::antiradiance {

namespace {

constexpr size_t kPatchesPerBlock = 64;

// K (diffuse, §4.2 fast path: E first, then the cosine lobe) and J for one patch; returns E.
glm::vec3 reflect_diffuse(const Patch& patch, float area, const DirectionalBins& bins,
                          float bin_solid_angle, std::span<const glm::vec3> incident,
                          std::span<glm::vec3> exitant) {
  const int m = bins.bin_count();
  glm::vec3 irradiance(0.0f);
  for (int j = 0; j < m; ++j) {
    const float cosine = glm::dot(patch.normal, bins.direction(j));
    // Travelling against the normal: arriving at the front.
    if (cosine < 0.0f) irradiance -= cosine * incident[size_t(j)];
  }
  irradiance *= bin_solid_angle;
  const glm::vec3 reflected = area * (patch.albedo * std::numbers::inv_pi_v<float>)*irradiance;
  for (int j = 0; j < m; ++j) {
    const float cosine = glm::dot(patch.normal, bins.direction(j));
    // Front: I_L = a cos (ρ/π) E. Back: −I_A = −a ⟨n|−ω_j⟩ L_in(ω_j) = a cos L_in(ω_j).
    exitant[size_t(j)] = cosine > 0.0f ? cosine * reflected : area * cosine * incident[size_t(j)];
  }
  return irradiance;
}

// The per-patch dispatch on the material's lobe (glossy lobes go here).
glm::vec3 reflect_patch(const Patch& patch, float area, const DirectionalBins& bins,
                        float bin_solid_angle, std::span<const glm::vec3> incident,
                        std::span<glm::vec3> exitant) {
  return reflect_diffuse(patch, area, bins, bin_solid_angle, incident, exitant);
}

}  // namespace

void local_pass(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                RadianceTables& tables) {
  if (tables.element_count() != hierarchy.element_count() ||
      tables.patch_count() != hierarchy.patch_count() || tables.bin_count() != bins.bin_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "radiance tables do not match the hierarchy");
  }
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  const float bin_solid_angle = float(bins.solid_angle());
  const std::span<glm::vec3> accumulated = tables.accumulated_irradiance();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        const Patch& patch = patches[p];
                        const uint32_t e = patch.element;
                        accumulated[p] +=
                            reflect_patch(patch, elements[e].area, bins, bin_solid_angle,
                                          tables.incident(e), tables.exitant(e));
                      }
                    });
}

}  // namespace bakegi::antiradiance
