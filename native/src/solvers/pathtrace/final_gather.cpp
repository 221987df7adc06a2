#include "solvers/pathtrace/final_gather.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "solvers/point_sampling.h"
#include "util/job_context.h"
#include "util/luminance.h"
#include "util/random.h"
#include "util/report.h"

namespace bakegi {

namespace {

// About four entries a bake point: measured on the suite's rooms, the blur of reading
// entries nearby fell from 7% (one entry per four points) to under 1% (docs/benchmarks.md).
constexpr uint64_t kEntriesPerPoint = 4;
constexpr uint64_t kMinEntries = 1024;
constexpr uint64_t kMaxEntries = uint64_t(1) << 18;
constexpr uint64_t kPilotRaysPerEntry = 2;
// Refinement doubles the paths per entry up to this many.
constexpr int64_t kMaxPaths = 1024;
// The cache's error may take this part of the target (the samples then aim at 0.87 of it).
constexpr double kErrorShare = 0.5;
// Beyond this part of the target after refinement the final gather is left out.
constexpr double kMaxErrorShare = 0.9;

struct CacheError {
  double error = 0.0;  // relative
  double mean = 0.0;   // mean luminance of the gathered values at the measured points
};

CacheError measure(const DirectLight& direct, const GatherCache& cache, const BakePoints& points,
                   int max_bounces, uint64_t seed, JobContext& context) {
  const size_t n = points.size();
  const size_t count = std::min<size_t>(n, kMeasuredPoints);
  std::vector<double> error_squared(count, 0.0), mean(count, 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 16),
                    [&](const tbb::blocked_range<size_t>& range) {
                      context.throw_if_cancelled();
                      uint64_t rays = 0;
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const size_t p = i * n / count;
                        const SurfacePoint x{points.positions[p], points.normals[p],
                                             points.normals[p]};
                        double sum = 0.0, sum_squares = 0.0, values = 0.0;
                        for (int k = 0; k < kMeasuredGathers; ++k) {
                          RandomStream rng = sample_stream(seed, p, uint64_t(k));
                          glm::vec3 difference(0.0f);
                          const glm::vec3 value = sample_indirect_gathered(
                              direct, cache, x, rng, max_bounces, rays, &difference);
                          const double d = luminance(difference);
                          sum += d;
                          sum_squares += d * d;
                          values += luminance(value);
                        }
                        const double k = double(kMeasuredGathers);
                        const double m = sum / k;
                        const double spread = std::max(0.0, (sum_squares - k * m * m) / (k - 1.0));
                        error_squared[i] = std::max(0.0, m * m - spread / k);
                        mean[i] = values / k;
                      }
                      context.report().add_count("rays", rays);
                    });
  CacheError result;
  double error_sum = 0.0;
  for (size_t i = 0; i < count; ++i) {
    error_sum += error_squared[i];
    result.mean += mean[i];
  }
  if (count == 0) return result;
  result.mean /= double(count);
  if (result.mean > 0.0) result.error = std::sqrt(error_sum / double(count)) / result.mean;
  return result;
}

std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * fraction);
  return text;
}

}  // namespace

FinalGather build_final_gather(const DirectLight& direct, const BakePoints& points,
                               const FinalGatherSettings& settings, JobContext& context) {
  FinalGather result;
  Report& report = context.report();
  if (points.size() == 0 || settings.max_bounces < 2) return result;
  context.set_stage_text("final gather: placing the cache");
  double area = 0.0;
  for (const Triangle& t : direct.scene().triangles) area += double(t.area);
  const uint64_t wanted =
      std::clamp<uint64_t>(kEntriesPerPoint * points.size(), kMinEntries, kMaxEntries);
  const float cell = GatherCache::cell_for(area, wanted);
  uint64_t rays = 0;
  const std::vector<SurfacePoint> entries = GatherCache::place_entries(
      direct, points, cell, kPilotRaysPerEntry * wanted, settings.seed, rays, context);
  report.add_count("rays", rays);
  if (entries.empty()) return result;

  BakePoints at;
  for (const SurfacePoint& e : entries) {
    at.positions.push_back(e.position);
    at.normals.push_back(e.shading_normal);
  }
  const size_t m = entries.size();
  std::vector<glm::vec3> half_a(m, glm::vec3(0.0f)), half_b(m, glm::vec3(0.0f)), added(m);
  int64_t per_half = 0;
  // Adds `more` paths to each half, continuing each half's own sample sequence.
  const auto trace_halves = [&](int64_t more) {
    for (int h = 0; h < 2; ++h) {
      context.set_stage_text("final gather: " + std::to_string(2 * (per_half + more)) +
                             " paths at " + std::to_string(m) + " cache entries");
      SampleSettings sampling;
      sampling.samples = more;
      sampling.seed = int64_t(settings.seed + 1 + uint64_t(h));
      sampling.sample_offset = per_half;
      estimate_at_points(
          at, added, sampling,
          [&](const SurfacePoint& x, RandomStream& rng, uint64_t& r) {
            return sample_indirect(direct, x, rng, settings.max_bounces - 1, r);
          },
          context);
      std::vector<glm::vec3>& half = h == 0 ? half_a : half_b;
      const float old_weight = float(per_half) / float(per_half + more);
      for (size_t j = 0; j < m; ++j) {
        half[j] = half[j] * old_weight + added[j] * (1.0f - old_weight);
      }
    }
    per_half += more;
  };
  trace_halves(std::max<int64_t>(1, settings.paths / 2));
  for (;;) {
    result.cache = std::make_unique<GatherCache>(entries, half_a, half_b, cell);
    result.paths = 2 * per_half;
    context.set_stage_text("final gather: measuring the cache's noise");
    result.error =
        measure(direct, *result.cache, points, settings.max_bounces, settings.seed + 3, context)
            .error;
    if (!(settings.target_error > 0.0) || result.error <= kErrorShare * settings.target_error ||
        result.paths >= kMaxPaths) {
      break;
    }
    trace_halves(per_half);
  }
  report.set_number("final_gather_entries", double(m));
  report.set_number("final_gather_cell", double(cell));
  report.set_number("final_gather_paths", double(result.paths));
  report.set_number("final_gather_cache_error", result.error);
  if (settings.target_error > 0.0 && result.error > kMaxErrorShare * settings.target_error) {
    report.warn("final gather left out: its cache's noise (" + percent(result.error) + " with " +
                std::to_string(result.paths) + " paths an entry) leaves too little of the " +
                percent(settings.target_error) + " target; the paths are traced in full");
    report.set_number("final_gather_cache_error", 0.0);
    result.cache.reset();
    result.error = 0.0;
  }
  return result;
}

}  // namespace bakegi
