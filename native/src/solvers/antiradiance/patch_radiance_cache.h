// Antiradiance's solution as a radiance cache (solvers/radiance_cache.h): per patch the
// direct irradiance its shadow-ray samples measured and the indirect irradiance the
// iteration gathered, both piecewise constant, found from a ray hit by PatchLocator (never
// blurred across an edge; the back of a solid's face has no patch and no value).
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "solvers/antiradiance/patch_locator.h"
#include "solvers/radiance_cache.h"

namespace bakegi::antiradiance {

class PatchRadianceCache : public RadianceCache {
 public:
  // Values per patch, in ElementHierarchy::patches() order (the locator's indices); both
  // vectors have one entry per patch. `scene` (the locator's) must outlive the cache.
  PatchRadianceCache(const Scene& scene, PatchLocator locator,
                     std::vector<glm::vec3> direct_over_pi,
                     std::vector<glm::vec3> indirect_over_pi);

  bool irradiance_at(const Hit& hit, const glm::vec3& direction,
                     CachedIrradiance& out) const override;
  size_t memory_bytes() const override;

 private:
  const Scene* scene_;
  PatchLocator locator_;
  std::vector<glm::vec3> direct_over_pi_;
  std::vector<glm::vec3> indirect_over_pi_;
};

}  // namespace bakegi::antiradiance
