// Every bake estimates its own error, so that a wrong result is flagged rather than trusted:
// at a few hundred probes (bake/error_probes.h) the path tracer estimates the truth, and the
// bake's values there are compared with it.
//
// The estimator. At probe i the path tracer's mean r_i of S samples has variance v_i =
// s_i^2 / S (s_i^2: the samples' luminance variance), so with d_i = Y(baked_i) - Y(r_i),
// E[d_i^2 - v_i] = (Y(baked_i) - Y(truth_i))^2: the probes' own noise is removed in
// expectation, and
//     NRMSE = sqrt(max(0, mean_i(d_i^2 - v_i))) / mean_i(Y(r_i))
// estimates the NRMSE of the bake over the points the probes were drawn from (the project's
// metric, luminance Y = 0.2126 R + 0.7152 G + 0.0722 B); the means are weighted by the
// probes' sampling weights (error_probes.h: probes at bake points are drawn half by the
// bake's light, so each counts 1 / (n q)). Its 90% interval comes from a bootstrap over the
// probes. For the path tracer itself the estimate is its noise; the
// probes use other random streams than the bake.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bake/error_probes.h"

namespace bakegi {

class DirectLight;
class JobContext;

// One set of probes' verdict.
struct ProbeErrorStatistics {
  size_t probes = 0;
  double nrmse = 0.0;           // NaN when the probes saw no indirect light at all
  double low = 0.0, high = 0.0;  // 90% bootstrap interval of nrmse
  double mean_reference = 0.0;   // mean luminance of the path-traced probe values
  double probe_noise = 0.0;      // sqrt(mean v_i) / mean_reference: the probes' own noise
};

struct ObjectErrorEstimate {
  uint32_t object_id = 0;
  ProbeErrorStatistics at_points, display;  // probes == 0 where the object has too few
};

struct ErrorEstimate {
  ProbeErrorStatistics at_points;  // probes at bake points: the solver's error
  ProbeErrorStatistics display;    // probes inside faces: what a viewer sees (may be empty)
  std::vector<ObjectErrorEstimate> objects;  // objects with enough probes of either kind
  int64_t samples = 0;                       // path-traced samples per probe
  uint64_t rays = 0;
};

struct ErrorEstimateSettings {
  int64_t samples = 512;  // per probe
  uint64_t seed = 0;      // the bake's seed; the probes' streams are derived from it
  int max_bounces = 64;
};

// `baked` holds the bake's results at the bake points the probes' stencils refer to.
ErrorEstimate estimate_error(const DirectLight& direct, const ErrorProbes& at_points,
                             const ErrorProbes& display, const std::vector<glm::vec3>& baked,
                             const ErrorEstimateSettings& settings, JobContext& context);

// The report's "error_estimate" member (a JSON object).
std::string error_estimate_json(const ErrorEstimate& estimate);

}  // namespace bakegi
