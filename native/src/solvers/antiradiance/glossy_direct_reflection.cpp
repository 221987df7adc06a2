#include "solvers/antiradiance/glossy_direct_reflection.h"

#include <algorithm>

#include "util/sampling.h"

namespace bakegi::antiradiance {

void reflect_direct_glossy(const glm::vec3& normal, const DirectionalBins& bins,
                           const GlossyLobeTable& table, std::span<const BinnedIrradiance> incident,
                           const glm::vec3& reflectable, std::span<glm::vec3> out,
                           std::vector<glm::vec3>& scratch) {
  const int m = bins.bin_count();
  std::fill(out.begin(), out.begin() + m, glm::vec3(0.0f));
  if (incident.empty() || !(max_component(reflectable) > 0.0f)) return;
  scratch.assign(size_t(m), glm::vec3(0.0f));
  for (const BinnedIrradiance& e : incident) scratch[e.bin] += e.irradiance;
  const float bin_solid_angle = float(bins.solid_angle());
  glm::vec3 reflected_flux(0.0f);
  for (int j = 0; j < m; ++j) {
    const glm::vec3& direction = bins.direction(j);
    const float cosine = glm::dot(normal, direction);
    if (cosine <= 0.0f) continue;
    // Light travelling along `mirror` leaves along ω_j after a mirror reflection.
    const glm::vec3 mirror = direction - 2.0f * cosine * normal;
    glm::vec3 gathered(0.0f);
    float weight_sum = 0.0f;
    for (const LobeWeight& w : table.lobe(bins.bin_of(mirror))) {
      gathered += w.weight * scratch[w.bin];
      const float incident_cosine = -glm::dot(normal, bins.direction(w.bin));
      if (incident_cosine > 0.0f) weight_sum += w.weight * incident_cosine;
    }
    if (!(weight_sum > 0.0f)) continue;
    const glm::vec3 radiance =
        gathered * (table.directional_albedo(cosine) / (bin_solid_angle * weight_sum));
    out[size_t(j)] = radiance;
    reflected_flux += (bin_solid_angle * cosine) * radiance;
  }
  // Direct light is never negative (no antiradiance yet): the flux always matches.
  for (int k = 0; k < 3; ++k) {
    if (!(reflected_flux[k] > 0.0f)) continue;
    const float scale = std::max(reflectable[k], 0.0f) / reflected_flux[k];
    for (int j = 0; j < m; ++j) out[size_t(j)][k] *= scale;
  }
}

}  // namespace bakegi::antiradiance
