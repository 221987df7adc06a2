// A final gather for a path-traced bake (setting final_gather): builds the cache
// (gather_cache.h) and measures the error its noise adds to the bake, refining it until that
// error is a small part of the target.
//
// The noise of the cache is shared: neighbouring bake points read the same entries, so it
// is not in any point's own sample variance and the adaptive sampler cannot see it. It is
// measured instead from the two independent halves every entry is path-traced in: at
// kMeasuredPoints bake points, kMeasuredGathers gathers each read the cache's half difference
// (a sample of its noise) as well as its value; the mean of that over a point's gathers, less
// its own sampling spread (squared, an unbiased estimate), is the cache's error there. The
// root mean over the points, relative to their mean value, is FinalGather::error; the
// sampler then aims its own noise at sqrt(target² - error²). What the halves cannot show is
// the blur of reading entries near a hit instead of at it (interpolation bias): the cells
// are small for that (about four entries a bake point), and the error probes measure it.
#pragma once

#include <cstdint>
#include <memory>

#include "scene/bake_points.h"
#include "solvers/pathtrace/gather_cache.h"

namespace bakegi {

class DirectLight;
class JobContext;
class Report;

struct FinalGatherSettings {
  int64_t paths = 16;         // per entry to begin with (both halves together)
  double target_error = 0.0;  // 0: no refinement
  int max_bounces = 64;
  uint64_t seed = 0;
};

struct FinalGather {
  std::unique_ptr<GatherCache> cache;  // null: no final gather (see the report)
  double error = 0.0;                  // relative NRMSE the cache's noise adds
  int64_t paths = 0;                   // per entry
};

FinalGather build_final_gather(const DirectLight& direct, const BakePoints& points,
                               const FinalGatherSettings& settings, JobContext& context);

inline constexpr uint64_t kMeasuredPoints = 1024;
inline constexpr int kMeasuredGathers = 64;

}  // namespace bakegi
