#include "solvers/point_sampling.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "field/noise_filter.h"
#include "settings/settings.h"
#include "solvers/adaptive_sampling.h"
#include "solvers/solver.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/report.h"
#include "util/sampling.h"
#include "util/luminance.h"

namespace bakegi {

namespace {

// Points per block: small enough for smooth load balancing, large enough that the
// per-block bookkeeping (a report lock) is negligible.
constexpr size_t kPointsPerBlock = 16;
// Cancel and progress are checked every this many samples of a point, so that a point
// with millions of samples still stops promptly (one sample costs microseconds).
constexpr int64_t kSamplesPerCheck = 32;

}  // namespace

SampleSettings SampleSettings::from(const Settings& given) {
  // The sampling settings are common: every method's schema has them alike.
  const SettingReader settings(given, method_schema("pathtrace"));
  SampleSettings s;
  s.samples = settings.get_int("samples");
  s.seed = settings.get_int("seed");
  s.sample_offset = settings.get_int("sample_offset");
  s.target_error = settings.get_float("target_error");
  return s;
}

namespace {

// One point's running sums: the value (the result) and its luminance (the noise estimate).
struct PointSums {
  glm::dvec3 value{0.0};
  PointTally tally;

  glm::vec3 mean() const {
    return tally.samples > 0 ? glm::vec3(value / double(tally.samples)) : glm::vec3(0.0f);
  }
};

// The first round of an adaptive bake: enough samples for a first variance estimate.
constexpr int64_t kFirstRoundSamples = 16;

// Adds samples [from, from + count) of every point with count > 0 (count_of(i)) to its sums,
// in parallel; progress runs from `progress_from` to `progress_to` over the round.
template <typename CountOf>
void sample_round(const BakePoints& points, std::vector<PointSums>& sums,
                  const SampleSettings& sampling, const PointSampleEstimator& estimator,
                  CountOf count_of, uint64_t round_samples, double progress_from,
                  double progress_to, std::atomic<uint64_t>& dropped, JobContext& context) {
  std::atomic<uint64_t> done_samples{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, points.size(), kPointsPerBlock),
      [&](const tbb::blocked_range<size_t>& block) {
        uint64_t rays = 0;
        uint64_t block_dropped = 0;
        for (size_t i = block.begin(); i != block.end(); ++i) {
          const int64_t count = count_of(i);
          if (count <= 0) continue;
          const SurfacePoint x{points.positions[i], points.normals[i], points.normals[i]};
          PointSums& point = sums[i];
          const int64_t from = point.tally.samples, to = from + count;
          for (int64_t first = from; first < to; first += kSamplesPerCheck) {
            context.throw_if_cancelled();
            const int64_t last = std::min(to, first + kSamplesPerCheck);
            for (int64_t s = first; s < last; ++s) {
              RandomStream rng = sobol_sample_stream(uint64_t(sampling.seed), i,
                                                     uint64_t(sampling.sample_offset + s));
              const glm::vec3 value = estimator(x, rng, rays);
              // A non-finite sample would poison the point; drop it (it counts as 0) and
              // say so in the report.
              if (is_finite(value)) {
                point.value += glm::dvec3(value);
                const double y = luminance(value);
                point.tally.luminance_sum += y;
                point.tally.luminance_squares += y * y;
              } else {
                ++block_dropped;
              }
            }
            point.tally.samples += last - first;
            const uint64_t done =
                done_samples.fetch_add(uint64_t(last - first), std::memory_order_relaxed) +
                uint64_t(last - first);
            context.set_stage_progress(progress_from + (progress_to - progress_from) *
                                                           double(done) / double(round_samples));
          }
        }
        context.report().add_count("rays", rays);
        if (block_dropped) dropped.fetch_add(block_dropped, std::memory_order_relaxed);
      },
      tbb::simple_partitioner());
}

}  // namespace

void estimate_at_points(const BakePoints& points, std::span<glm::vec3> out,
                        const SampleSettings& sampling, const PointSampleEstimator& estimator,
                        JobContext& context, std::span<float> variance_of_mean,
                        const NoiseFilter* after) {
  if (out.size() != points.size() ||
      (!variance_of_mean.empty() && variance_of_mean.size() != points.size())) {
    throw Error(BAKEGI_ERROR_INTERNAL, "output size does not match the number of bake points");
  }
  const size_t count = points.size();
  std::vector<PointSums> sums(count);
  std::atomic<uint64_t> dropped{0};
  context.set_stage_progress(0.0);
  Report& report = context.report();
  if (!(sampling.target_error > 0.0)) {
    context.set_stage_text("tracing " + std::to_string(sampling.samples) + " samples at " +
                           std::to_string(count) + " points");
    sample_round(
        points, sums, sampling, estimator, [&](size_t) { return sampling.samples; },
        uint64_t(sampling.samples) * count, 0.0, 1.0, dropped, context);
  } else {
    // Rounds until the predicted error meets the target (solvers/adaptive_sampling.h). The
    // k-th round's progress fills [1 - 2^-k, 1 - 2^-(k+1)): the number of rounds is not known.
    const int64_t first = std::min(kFirstRoundSamples, sampling.samples);
    context.set_stage_text("tracing towards " + std::to_string(sampling.target_error * 100.0) +
                           "% error at " + std::to_string(count) + " points");
    sample_round(
        points, sums, sampling, estimator, [&](size_t) { return first; },
        uint64_t(first) * count, 0.0, 0.5, dropped, context);
    std::vector<PointTally> tallies(count);
    std::vector<glm::vec3> means;
    std::vector<float> variances;
    double slice = 0.5;
    int64_t rounds = 1;
    for (;;) {
      for (size_t i = 0; i < count; ++i) tallies[i] = sums[i].tally;
      // With a filter after the bake the raw noise may be larger by what the filter takes
      // out, less what its bias adds (error² = (left · noise)² + bias²), both measured again
      // each round (the filter takes out less, and adds less, as the noise falls below the
      // differences between neighbours). Where its bias alone exceeds the target the rounds
      // aim at the raw target, as without the filter. A filter that keeps the raw means
      // (NoiseFilter::changes_values) only scales their noise: what the variances overstate.
      FilteredNoise filtered;
      double target = sampling.target_error;
      if (after) {
        means.resize(count);
        variances.resize(count);
        for (size_t i = 0; i < count; ++i) {
          means[i] = sums[i].mean();
          variances[i] = float(luminance_variance_of_mean(sums[i].tally));
        }
        filtered = after->predict(means, variances, context);
        filtered.noise_left = std::clamp(filtered.noise_left, 1e-3, 1.0);
        if (filtered.bias < target) {
          target = std::sqrt(target * target - filtered.bias * filtered.bias) /
                   filtered.noise_left;
        }
      }
      const SamplingRound next = plan_sampling_round(tallies, target, sampling.samples);
      const double noise = next.predicted_error * filtered.noise_left;
      report.set_number("sampling_predicted_error",
                        std::sqrt(noise * noise + filtered.bias * filtered.bias));
      if (after && after->changes_values()) {
        report.set_number("sampling_noise_left_by_filter", filtered.noise_left);
        report.set_number("sampling_filter_bias", filtered.bias);
      } else if (after) {
        report.set_number("sampling_noise_scale", filtered.noise_left * filtered.noise_left);
      }
      if (next.done()) break;
      sample_round(
          points, sums, sampling, estimator, [&](size_t i) { return next.added[i]; },
          uint64_t(next.added_samples), 1.0 - slice, 1.0 - slice / 2.0, dropped, context);
      slice /= 2.0;
      ++rounds;
    }
    report.add_count("sampling_rounds", uint64_t(rounds));
    report.set_number("target_error", sampling.target_error);
  }
  uint64_t total = 0;
  for (size_t i = 0; i < count; ++i) {
    const PointSums& point = sums[i];
    total += uint64_t(point.tally.samples);
    out[i] = point.mean();
    if (!variance_of_mean.empty()) {
      variance_of_mean[i] = float(luminance_variance_of_mean(point.tally));
    }
  }
  if (dropped.load() > 0) {
    report.warn(std::to_string(dropped.load()) + " non-finite Monte Carlo samples were dropped");
  }
  report.add_count("samples", total);
}

}  // namespace bakegi
