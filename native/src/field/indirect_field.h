// What a solver returns: indirect light that can be evaluated at any (position, normal),
// in the output convention (E_indirect / pi). Output never depends on which solver made it.
//
// One ownership rule for every field: it refers (by reference, or by pointer where optional)
// to what the job keeps alive until the field has been evaluated (the Scene, the ray tracer,
// the DirectLight; BakeJob::finish releases them after); it shares the precomputation
// (shared_ptr to const, so a relight or a later job may keep it); and it owns what it
// computed for this bake (irradiance per basis point or patch, interpolation tables).
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "scene/bake_points.h"

namespace bakegi {

class JobContext;
class NoiseFilter;

class IndirectField {
 public:
  virtual ~IndirectField() = default;
  // Writes one RGB value per point. May be long (the path tracer traces here): reports
  // progress and honours cancel through the context.
  virtual void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                        JobContext& context) const = 0;
  // evaluate(), and for a Monte Carlo field each point's variance of its luminance (the
  // noise a denoiser may trade for bias, bake/point_denoiser.h): returns true when
  // `variance_of_mean` (one per point) was filled, false (and nothing written there) for a
  // field without noise estimates. `after`, when given, is what the bake will filter the
  // result with: a field that samples to a target error aims at the noise left after it.
  virtual bool evaluate_with_variance(const BakePoints& points, std::span<glm::vec3> out,
                                      std::span<float> variance_of_mean, const NoiseFilter* after,
                                      JobContext& context) const {
    (void)variance_of_mean;
    (void)after;
    evaluate(points, out, context);
    return false;
  }
};

}  // namespace bakegi
