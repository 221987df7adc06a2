// Eq. 16 of Lehtinen et al. 2008: the links from ALL senders to one receiver by a single
// hemispherical gathering integral, so every sender shares the receiver's rays:
//
//   T'_ij = ∫_Ω(i) B_j(r(x_i, ω)) ρ(r(x_i, ω)) / π  ω̄ dω
//
// r(x, ω) is the first hit along the ray, ρ its diffuse albedo (texture applied) and ω̄ the
// unit direction: vector irradiance at x_i per unit scalar irradiance of sender j. (The
// paper writes ρ for the reflected radiance per unit irradiance, ρ/π for a Lambertian
// surface.) Estimated with stratified uniform hemisphere directions (density 1/2π: the
// tangential components of ω̄ stay bounded, unlike with cosine sampling).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/transfer_links.h"

namespace bakegi {
struct Scene;
class RayTracer;
}  // namespace bakegi

namespace bakegi::meshless {

struct VisibleRelations;

// Dense accumulator over the senders with a list of the ones touched, reused across
// receivers by one thread (clearing costs only what was touched).
class SenderAccumulator {
 public:
  explicit SenderAccumulator(uint32_t sender_count)
      : values_(sender_count, LinkValue(0.0f)), touched_flag_(sender_count, 0) {}
  LinkValue& at(uint32_t sender) {
    if (!touched_flag_[sender]) {
      touched_flag_[sender] = 1;
      touched_.push_back(sender);
    }
    return values_[sender];
  }
  // The value of a sender, zero if untouched.
  const LinkValue& value(uint32_t sender) const { return values_[sender]; }
  const std::vector<uint32_t>& touched() const { return touched_; }
  void clear() {
    for (uint32_t s : touched_) {
      values_[s] = LinkValue(0.0f);
      touched_flag_[s] = 0;
    }
    touched_.clear();
  }

 private:
  std::vector<LinkValue> values_;
  std::vector<uint8_t> touched_flag_;
  std::vector<uint32_t> touched_;
};

struct GatherSettings {
  uint32_t rays = 256;        // hemisphere rays per receiver (stratified, a square count is best)
  uint64_t seed = 0;          // ray stream: sample_stream(seed, receiver, 0)
  float ray_epsilon = 1e-4f;  // origin offset along the receiver's normal
  // A ray's hit point evaluates only the sender functions whose point it sees, renormalized
  // per level (visible_basis.h): a coarse sender centred behind a wall does not hand its
  // coefficient to surfaces on this side of it. One occlusion ray per candidate function.
  bool visibility = true;
  // The senders' visible coarser relations (visible_basis.h, of a hierarchy whose first
  // levels are the senders): a hit that sees a finer sender level but none of a coarser one
  // takes the finest level it sees with those points' coarser relations instead
  // (level_completion.h). Null: a level the hit does not see adds nothing.
  const VisibleRelations* completion = nullptr;
  // Per material: the glossy lobe's hemispherical albedo (ρ_g times
  // phong_hemispherical_albedo), added to the diffuse albedo at a hit. The method transports
  // diffuse light only; folding a lobe keeps its energy and loses its direction. Null: lobes
  // reflect nothing.
  const std::vector<glm::vec3>* glossy_as_diffuse = nullptr;
};

// What GatherSettings::glossy_as_diffuse holds for a scene's materials.
std::vector<glm::vec3> glossy_as_diffuse(const Scene& scene);

// Adds T'_ij for every sender j of `senders` (the first sender levels of the basis, see
// TransferOperator::sender_count) into `out`; returns the number of hemisphere rays cast
// (`visibility_rays`, if given, gets the occlusion rays of the visibility test added;
// `hits_completed` the hits that had a level completed).
uint64_t gather_links(const Scene& scene, const RayTracer& tracer, const BasisHierarchy& senders,
                      const glm::vec3& position, const glm::vec3& normal, uint64_t receiver,
                      const GatherSettings& settings, SenderAccumulator& out,
                      std::vector<BasisValue>& scratch, uint64_t* visibility_rays = nullptr,
                      uint64_t* hits_completed = nullptr);

}  // namespace bakegi::meshless
