#include "solvers/direct_only/direct_only_solver.h"

#include "lights/direct_light.h"
#include "util/sampling.h"
#include "settings/settings.h"

namespace bakegi {

DirectLightField::DirectLightField(const DirectLight& direct, const SampleSettings& settings)
    : direct_(direct), settings_(settings) {}

void DirectLightField::evaluate(const BakePoints& points, std::span<glm::vec3> out,
                                JobContext& context) const {
  estimate_at_points(
      points, out, settings_,
      [&](const SurfacePoint& x, RandomStream& rng, uint64_t& rays) {
        return direct_.irradiance_sample(x, rng, rays) * kInvPi;
      },
      context);
}

std::unique_ptr<IndirectField> DirectOnlySolver::solve(const SolveInputs& inputs,
                                                       JobContext& context) {
  return std::make_unique<DirectLightField>(inputs.direct, SampleSettings::from(inputs.settings));
}

}  // namespace bakegi
