// Path guiding at the bake point (issue 15): where the indirect light arrives from, learned
// per region, so that first directions go where it is.
//
// A bake point's indirect light is an integral over directions of L(ω) cos/π. Where L is
// large in a small solid angle (a spot light's pool seen across Sponza, a sun patch on an
// office floor), cosine-weighted directions find it rarely and that rarity is the noise.
// Here the bake points are grouped into regions (a grid cell and the axis their normal is
// closest to), a few cosine-weighted training paths per point add their value to a histogram
// of directions per region (equal-area bins over the sphere: z = cos θ and φ uniform), and
// bake paths then draw their first direction from a mixture: kCosineShare cosine-weighted,
// the rest from the region's histogram, weighted by the mixture's density (one-sample MIS,
// balance heuristic). The result is unbiased whatever the histograms hold: the cosine part
// reaches every direction; a poor histogram costs noise, not accuracy.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bake_points.h"

namespace bakegi {

class DirectLight;
class JobContext;

class DirectionGuide {
 public:
  static constexpr int kZBins = 16;
  static constexpr int kPhiBins = 32;
  static constexpr int kBins = kZBins * kPhiBins;
  static constexpr float kCosineShare = 0.5f;
  // Regions hold about this many bake points.
  static constexpr double kPointsPerRegion = 256.0;

  // Regions over `points`; each point traces `paths` cosine-weighted training paths
  // (streams from `seed`) into its region's histogram. Parallel; checks cancel.
  DirectionGuide(const DirectLight& direct, const BakePoints& points, int paths, int max_bounces,
                 uint64_t seed, JobContext& context);

  // The region of a bake point, or -1 (a point not among the training points' regions).
  int region_of(const glm::vec3& position, const glm::vec3& normal) const;
  // A direction from region `region`'s histogram (u1, u2 in [0, 1)) and its density (per
  // steradian) under that histogram.
  glm::vec3 sample(int region, float u1, float u2) const;
  float pdf(int region, const glm::vec3& direction) const;

  size_t regions() const { return cdf_.size() / kBins; }
  uint64_t rays() const { return rays_; }

 private:
  uint64_t key_of(const glm::vec3& position, const glm::vec3& normal) const;

  float cell_ = 1.0f;
  glm::vec3 origin_{0.0f};
  std::unordered_map<uint64_t, int> region_of_key_;
  std::vector<float> cdf_;          // per region, kBins running sums ending at 1
  std::vector<float> probability_;  // per region and bin
  uint64_t rays_ = 0;
};

}  // namespace bakegi
