#include "solvers/antiradiance/local_pass.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "solvers/antiradiance/glossy_lobe_table.h"
#include "util/error.h"
#include "util/sampling.h"

namespace bakegi::antiradiance {

namespace {

constexpr size_t kPatchesPerBlock = 64;

// Which hemispheres of a patch's I_ex row a local pass writes.
enum class Update {
  kBoth,              // K on the front, J on the back (local_pass)
  kRadianceOnly,      // K on the front, the back zeroed
  kAntiradianceOnly,  // J on the back, the front kept
};

// Glossy radiance per unit ρ_g towards every front bin (0 elsewhere) into `out`: per outgoing
// bin, the lobe around the mirror image of ω_j gathered from the front incident bins and
// normalized to the analytic directional albedo A(⟨n|ω_j⟩) (a uniform field reflects exactly
// A L); then per channel the whole row is scaled so that the reflected flux equals
// Σ_l A(μ_l) ⟨n|−ω_l⟩ L_in(ω_l), what the incident light can give (no energy from bins that
// several outgoing lobes share). Rescaled only when both are positive (antiradiance can make
// a row's net incident light negative, where a ratio means nothing).
void reflect_glossy(const Patch& patch, const DirectionalBins& bins, const GlossyLobeTable& table,
                    std::span<const glm::vec3> incident, std::span<glm::vec3> out) {
  const int m = bins.bin_count();
  glm::vec3 reflected_flux(0.0f), allowed_flux(0.0f);
  for (int j = 0; j < m; ++j) {
    const glm::vec3& direction = bins.direction(j);
    const float cosine = glm::dot(patch.normal, direction);
    if (cosine < 0.0f) {
      allowed_flux -= table.directional_albedo(-cosine) * cosine * incident[size_t(j)];
    }
    if (cosine <= 0.0f) {
      out[size_t(j)] = glm::vec3(0.0f);
      continue;
    }
    // Light travelling along `mirror` leaves along ω_j after a mirror reflection.
    const glm::vec3 mirror = direction - 2.0f * cosine * patch.normal;
    glm::vec3 gathered(0.0f);
    float weight_sum = 0.0f;
    for (const LobeWeight& w : table.lobe(bins.bin_of(mirror))) {
      const float incident_cosine = -glm::dot(patch.normal, bins.direction(w.bin));
      if (incident_cosine <= 0.0f) continue;
      gathered += (w.weight * incident_cosine) * incident[w.bin];
      weight_sum += w.weight * incident_cosine;
    }
    const glm::vec3 radiance = weight_sum > 0.0f
                                   ? gathered * (table.directional_albedo(cosine) / weight_sum)
                                   : glm::vec3(0.0f);
    out[size_t(j)] = radiance;
    reflected_flux += cosine * radiance;
  }
  for (int k = 0; k < 3; ++k) {
    if (!(reflected_flux[k] > 0.0f) || !(allowed_flux[k] > 0.0f)) continue;
    const float scale = allowed_flux[k] / reflected_flux[k];
    for (int j = 0; j < m; ++j) out[size_t(j)][k] *= scale;
  }
}

// K and J for one patch; returns E. K: E from the front bins, normalized by the bins'
// discrete cosine sum so that a uniform field gives exactly E = π L (§4.2 fast path: E first,
// then the cosine lobe), plus the glossy lobe when the patch has one. J: the back bins.
glm::vec3 reflect_patch(const Patch& patch, float area, const DirectionalBins& bins,
                        const GlossyLobeTable* glossy, std::span<const glm::vec3> incident,
                        std::span<glm::vec3> exitant, std::vector<glm::vec3>& scratch,
                        Update update = Update::kBoth) {
  const int m = bins.bin_count();
  glm::vec3 weighted(0.0f);
  float cosine_sum = 0.0f;
  for (int j = 0; j < m; ++j) {
    const float cosine = glm::dot(patch.normal, bins.direction(j));
    // Travelling against the normal: arriving at the front.
    if (cosine < 0.0f) {
      weighted -= cosine * incident[size_t(j)];
      cosine_sum -= cosine;
    }
  }
  // ω_bin Σ_l ⟨n|−ω_l⟩₊ ≈ π with a quadrature error of up to 0.7% at 192 bins (2.8% at 48)
  // that depends on the normal; dividing by it instead removes it.
  const glm::vec3 irradiance =
      cosine_sum > 0.0f ? weighted * (std::numbers::pi_v<float> / cosine_sum) : glm::vec3(0.0f);
  const glm::vec3 diffuse = patch.albedo * std::numbers::inv_pi_v<float> * irradiance;
  const bool with_glossy = glossy != nullptr && update != Update::kAntiradianceOnly;
  if (with_glossy) {
    scratch.resize(size_t(m));
    reflect_glossy(patch, bins, *glossy, incident, scratch);
  }
  for (int j = 0; j < m; ++j) {
    const float cosine = glm::dot(patch.normal, bins.direction(j));
    // Front: I_L = a cos L_reflected. Back: −I_A = −a ⟨n|−ω_j⟩ L_in(ω_j) = a cos L_in(ω_j).
    if (cosine > 0.0f) {
      if (update == Update::kAntiradianceOnly) continue;
      const glm::vec3 reflected =
          with_glossy ? diffuse + patch.glossy * scratch[size_t(j)] : diffuse;
      exitant[size_t(j)] = (area * cosine) * reflected;
    } else if (update == Update::kRadianceOnly) {
      exitant[size_t(j)] = glm::vec3(0.0f);
    } else {
      exitant[size_t(j)] = area * cosine * incident[size_t(j)];
    }
  }
  return irradiance;
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
                         RadianceTables& tables, Update update,
                         const JobContext* context = nullptr) {
  check_sizes(hierarchy, bins, tables);
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  std::vector<std::shared_ptr<const GlossyLobeTable>> keep_alive;
  const std::vector<const GlossyLobeTable*> glossy =
      glossy_tables_for_patches(patches, bins, keep_alive);
  const std::span<glm::vec3> accumulated = tables.accumulated_irradiance();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      std::vector<glm::vec3> scratch;
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        if (context && p % 64 == 0) context->throw_if_cancelled();
                        const Patch& patch = patches[p];
                        const uint32_t e = patch.element;
                        accumulated[p] +=
                            reflect_patch(patch, elements[e].area, bins, glossy[p],
                                          tables.incident(e), tables.exitant(e), scratch, update);
                      }
                    });
}

}  // namespace

void local_pass(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                RadianceTables& tables, const JobContext* context) {
  reflect_all_patches(hierarchy, bins, tables, Update::kBoth, context);
}

void local_pass_radiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                              RadianceTables& tables, const JobContext* context) {
  reflect_all_patches(hierarchy, bins, tables, Update::kRadianceOnly, context);
}

double local_pass_antiradiance_only(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                                    RadianceTables& tables, const JobContext* context) {
  check_sizes(hierarchy, bins, tables);
  const std::vector<Patch>& patches = hierarchy.patches();
  const std::vector<Element>& elements = hierarchy.elements();
  const int m = bins.bin_count();
  // Per-patch sums, added up in patch order afterwards: the same result for any thread count.
  std::vector<double> change(patches.size(), 0.0), magnitude(patches.size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, patches.size(), kPatchesPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      std::vector<glm::vec3> before(static_cast<size_t>(m)), scratch;
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        if (context && p % 64 == 0) context->throw_if_cancelled();
                        const Patch& patch = patches[p];
                        const uint32_t e = patch.element;
                        const std::span<glm::vec3> exitant = tables.exitant(e);
                        std::copy(exitant.begin(), exitant.end(), before.begin());
                        reflect_patch(patch, elements[e].area, bins, nullptr, tables.incident(e),
                                      exitant, scratch, Update::kAntiradianceOnly);
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
