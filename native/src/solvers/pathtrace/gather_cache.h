// A cache of the indirect light where a bake's gathers land, for a final gather (issue 15).
//
// In closed rooms 50-70% of the indirect light has bounced more than once (docs/benchmarks.md,
// section 0e), and most of the path tracer's noise is in those longer paths. With a final
// gather a bake point's path stops at its first hit y: the light reflected there is
// rho(y) (E_direct(y)/pi + E_indirect(y)/pi), the direct part sampled exactly as before and the
// indirect part read from this cache, which holds E_indirect/pi (the bake's own output
// quantity) at entries spread over the surfaces the gathers reach, each path-traced once.
// Every gather of a point reads many entries, so their noise averages out; what is left is
// the blur of reading an entry nearby instead of y itself (interpolation bias).
//
// Entries: one cosine-weighted pilot ray from the bake points, its hits thinned to one per
// grid cell and normal direction (6 axis-aligned buckets), so they cover the reached surfaces
// about evenly at the cell size, on the side the rays arrive from. Lookup: the entries of the
// 27 cells around y that face the same way (normals within kMinNormalCosine) and lie near
// y's plane, weighted by distance; none: the caller traces the path on (no bias there).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "lights/surface_point.h"
#include "scene/bake_points.h"

namespace bakegi {

class DirectLight;
class JobContext;

class GatherCache {
 public:
  // Where the entries go: hits of pilot rays from `points` (about 4 per wanted entry), one
  // kept per cell of size `cell` and normal bucket. Deterministic for a seed; parallel.
  static std::vector<SurfacePoint> place_entries(const DirectLight& direct,
                                                 const BakePoints& points, float cell,
                                                 uint64_t pilot_rays, uint64_t seed,
                                                 uint64_t& rays, JobContext& context);

  // The cell size that gives about `entries` entries on a scene of `area` m² of surfaces
  // (about half the area is reached from one side).
  static float cell_for(double area, uint64_t entries);

  // `half_a[i]`, `half_b[i]`: E_indirect/pi at entries[i] from two independent halves of its
  // paths; the cache holds their mean and half their difference, which has the mean's noise.
  GatherCache(const std::vector<SurfacePoint>& entries, const std::vector<glm::vec3>& half_a,
              const std::vector<glm::vec3>& half_b, float cell);

  struct Reading {
    glm::vec3 value;            // E_indirect/pi
    glm::vec3 half_difference;  // the same weights on (a - b) / 2: a sample of its noise
  };
  // The cached light at a surface point (normal on the side light arrives from); false where
  // no entry is near enough.
  bool lookup(const glm::vec3& position, const glm::vec3& normal, Reading& out) const;

  size_t size() const { return positions_.size(); }
  static constexpr uint64_t kBytesPerEntry = 4 * sizeof(glm::vec3) + 16;
  static constexpr float kMinNormalCosine = 0.8f;

 private:
  struct Slot {
    uint64_t key = ~uint64_t(0);  // empty
    uint32_t begin = 0, end = 0;  // into the entries, sorted by cell
  };
  const Slot* find(uint64_t key) const;

  float cell_;
  std::vector<glm::vec3> positions_, normals_, values_, half_differences_;
  std::vector<Slot> slots_;  // open addressing, power-of-two size
};

}  // namespace bakegi
