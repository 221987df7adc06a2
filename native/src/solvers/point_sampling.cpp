#include "solvers/point_sampling.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "settings/settings.h"
#include "solvers/solver.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"
#include "settings/settings.h"

namespace bakegi {

namespace {

// Points per block: small enough for smooth load balancing, large enough that the
// per-block bookkeeping (a report lock) is negligible.
constexpr size_t kPointsPerBlock = 16;
// Cancel and progress are checked every this many samples of a point, so that a point
// with millions of samples still stops promptly (one sample costs microseconds).
constexpr int64_t kSamplesPerCheck = 32;

bool is_finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

SampleSettings SampleSettings::from(const Settings& given) {
  // The sampling settings are common: every method's schema has them alike.
  const SettingReader settings(given, method_schema("pathtrace"));
  SampleSettings s;
  s.samples = settings.get_int("samples");
  s.seed = settings.get_int("seed");
  s.sample_offset = settings.get_int("sample_offset");
  return s;
}

void estimate_at_points(const BakePoints& points, std::span<glm::vec3> out,
                        const SampleSettings& sampling, const PointSampleEstimator& estimator,
                        JobContext& context) {
  if (out.size() != points.size()) {
    throw Error(BAKEGI_ERROR_INTERNAL, "output size does not match the number of bake points");
  }
  const size_t count = points.size();
  const double total_samples = double(count) * double(sampling.samples);
  std::atomic<uint64_t> done_samples{0};
  std::atomic<uint64_t> dropped{0};
  context.set_stage_text("tracing " + std::to_string(sampling.samples) + " samples at " +
                         std::to_string(count) + " points");
  context.set_stage_progress(0.0);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, count, kPointsPerBlock),
      [&](const tbb::blocked_range<size_t>& block) {
        uint64_t rays = 0;
        uint64_t block_dropped = 0;
        for (size_t i = block.begin(); i != block.end(); ++i) {
          const SurfacePoint x{points.positions[i], points.normals[i], points.normals[i]};
          glm::dvec3 sum(0.0);
          for (int64_t first = 0; first < sampling.samples; first += kSamplesPerCheck) {
            context.throw_if_cancelled();
            const int64_t last = std::min(sampling.samples, first + kSamplesPerCheck);
            for (int64_t s = first; s < last; ++s) {
              RandomStream rng = sobol_sample_stream(uint64_t(sampling.seed), i,
                                                     uint64_t(sampling.sample_offset + s));
              const glm::vec3 value = estimator(x, rng, rays);
              // A non-finite sample would poison the point; drop it and say so in the
              // report.
              if (is_finite(value)) {
                sum += glm::dvec3(value);
              } else {
                ++block_dropped;
              }
            }
            const uint64_t done =
                done_samples.fetch_add(uint64_t(last - first), std::memory_order_relaxed) +
                uint64_t(last - first);
            context.set_stage_progress(double(done) / total_samples);
          }
          out[i] = glm::vec3(sum / double(sampling.samples));
        }
        context.report().add_count("rays", rays);
        if (block_dropped) dropped.fetch_add(block_dropped, std::memory_order_relaxed);
      },
      tbb::simple_partitioner());
  if (dropped.load() > 0) {
    context.report().warn(std::to_string(dropped.load()) +
                          " non-finite Monte Carlo samples were dropped");
  }
  context.report().add_count("samples", uint64_t(sampling.samples) * count);
}

}  // namespace bakegi
