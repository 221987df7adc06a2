#include "solvers/antiradiance/local_pass.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace bakegi::antiradiance {

namespace {

constexpr size_t kPatchesPerBlock = 64;

// Which hemispheres of a patch's I_ex row a local pass writes.
enum class Update {
  kBoth,              // K on the front, J on the back (local_pass)
  kRadianceOnly,      // K on the front, the back zeroed
  kAntiradianceOnly,  // J on the back, the front kept
};

// K (diffuse, §4.2 fast path: E first, then the cosine lobe) and J for one patch; returns E.
glm::vec3 reflect_diffuse(const Patch& patch, float area, const DirectionalBins& bins,
                          float bin_solid_angle, std::span<const glm::vec3> incident,
                          std::span<glm::vec3> exitant, Update update = Update::kBoth) {
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
    if (cosine > 0.0f) {
      if (update != Update::kAntiradianceOnly) exitant[size_t(j)] = cosine * reflected;
    } else if (update == Update::kRadianceOnly) {
      exitant[size_t(j)] = glm::vec3(0.0f);
    } else {
      exitant[size_t(j)] = area * cosine * incident[size_t(j)];
    }
  }
  return irradiance;
}

// The per-patch dispatch on the material's lobe (glossy lobes go here).
glm::vec3 reflect_patch(const Patch& patch, float area, const DirectionalBins& bins,
                        float bin_solid_angle, std::span<const glm::vec3> incident,
                        std::span<glm::vec3> exitant, Update update = Update::kBoth) {
  return reflect_diffuse(patch, area, bins, bin_solid_angle, incident, exitant, update);
}

void check_sizes(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                 const RadianceTables& tables) {
  if (tables.element_count() != hierarchy.element_count() ||
      tables.patch_count() != hierarchy.patch_count() || tables.bin_count() != bins.bin_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "radiance tables do not match the hierarchy");
  }
}

double absolute_sum(glm::vec3 v) {
  return std::abs(double(v.x)) + std::abs(double(v.y)) + std::abs(double(v.z));
}

}  // namespace

namespace {

// K and/or J at every patch, adding each patch's E to E_acc (both modes that reflect).
void reflect_all_patches(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                         RadianceTables& tables, Update update) {
  check_sizes(hierarchy, bins, tables);
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
                                          tables.incident(e), tables.exitant(e), update);
                      }
                    });
}

}  // namespace

void local_pass(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                RadianceTables& tables) {
  reflect_all_patches(hierarchy, bins, tables, Update::kBoth);
}

void local_pass_radiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                              RadianceTables& tables) {
  reflect_all_patches(hierarchy, bins, tables, Update::kRadianceOnly);
}

double local_pass_antiradiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                                    RadianceTables& tables) {
  check_sizes(hierarchy, bins, tables);
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  const float bin_solid_angle = float(bins.solid_angle());
  const int m = bins.bin_count();
  // Per-patch sums, added up in patch order afterwards: the same result for any thread count.
  std::vector<double> change(patches.size(), 0.0), magnitude(patches.size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      std::vector<glm::vec3> before(static_cast<size_t>(m));
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        const Patch& patch = patches[p];
                        const uint32_t e = patch.element;
                        const std::span<glm::vec3> exitant = tables.exitant(e);
                        std::copy(exitant.begin(), exitant.end(), before.begin());
                        reflect_patch(patch, elements[e].area, bins, bin_solid_angle,
                                      tables.incident(e), exitant, Update::kAntiradianceOnly);
                        for (int j = 0; j < m; ++j) {
                          if (glm::dot(patch.normal, bins.direction(j)) > 0.0f) continue;
                          change[p] += absolute_sum(exitant[size_t(j)] - before[size_t(j)]);
                          magnitude[p] += absolute_sum(exitant[size_t(j)]);
                        }
                      }
                    });
  double total_change = 0.0, total_magnitude = 0.0;
  for (size_t p = 0; p < patches.size(); ++p) {
    total_change += change[p];
    total_magnitude += magnitude[p];
  }
  if (total_magnitude > 0.0) return total_change / total_magnitude;
  return total_change > 0.0 ? 1.0 : 0.0;
}

}  // namespace bakegi::antiradiance
