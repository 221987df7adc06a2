// What the bake does to a Monte Carlo field's noise after evaluating it (a denoiser,
// bake/point_denoiser.h): an adaptive sampler (solvers/adaptive_sampling.h) that knows it
// aims at the noise left after the filter, not at the noise of its raw means. Without a
// denoiser the bake gives one that only reads the noise's scale (bake_job.cpp).
#pragma once

#include <span>

#include <glm/glm.hpp>

namespace bakegi {

class JobContext;

// What a filter would make of values with a given noise, both in the NRMSE's units.
struct FilteredNoise {
  // The noise it leaves over the noise the variances it is given predict, in (0, 1] (below
  // the noise it takes out where the variances overstate the noise).
  double noise_left = 1.0;
  double bias = 0.0;  // the error it adds as far as it can tell, relative to the mean
};

class NoiseFilter {
 public:
  virtual ~NoiseFilter() = default;
  // For these values (one per evaluated point) and the variances of their means; does not
  // change them.
  virtual FilteredNoise predict(std::span<const glm::vec3> values,
                                std::span<const float> variance_of_mean,
                                JobContext& context) const = 0;
  // False for a filter that leaves the values as they are and only reads how much their
  // variances overstate their noise (noise_left, no bias): the bake keeps the raw means.
  virtual bool changes_values() const { return true; }
};

}  // namespace bakegi
