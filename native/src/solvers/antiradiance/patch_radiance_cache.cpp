#include "solvers/antiradiance/patch_radiance_cache.h"

#include "scene/scene.h"
#include "util/error.h"

namespace bakegi::antiradiance {

PatchRadianceCache::PatchRadianceCache(const Scene& scene, PatchLocator locator,
                                       std::vector<glm::vec3> direct_over_pi,
                                       std::vector<glm::vec3> indirect_over_pi)
    : scene_(&scene),
      locator_(std::move(locator)),
      direct_over_pi_(std::move(direct_over_pi)),
      indirect_over_pi_(std::move(indirect_over_pi)) {
  if (direct_over_pi_.size() != indirect_over_pi_.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "patch radiance cache: one value per patch expected");
  }
}

bool PatchRadianceCache::irradiance_at(const Hit& hit, const glm::vec3& direction,
                                       CachedIrradiance& out) const {
  const bool back = glm::dot(scene_->triangles[hit.triangle].face_normal, direction) > 0.0f;
  const uint32_t patch = locator_.find(hit.triangle, hit.b1, hit.b2, back);
  if (patch == PatchLocator::kNone || patch >= indirect_over_pi_.size()) return false;
  out.direct_over_pi = direct_over_pi_[patch];
  out.indirect_over_pi = indirect_over_pi_[patch];
  return true;
}

size_t PatchRadianceCache::memory_bytes() const {
  return locator_.memory_bytes() +
         (direct_over_pi_.capacity() + indirect_over_pi_.capacity()) * sizeof(glm::vec3);
}

}  // namespace bakegi::antiradiance
