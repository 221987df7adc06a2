#include "bake/error_estimate.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "lights/surface_point.h"
#include "solvers/pathtrace/indirect_path.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/report.h"
#include "util/luminance.h"

namespace bakegi {

namespace {

// Cancel and progress every this many samples of a probe (a sample costs microseconds).
constexpr int64_t kSamplesPerCheck = 32;
constexpr int kBootstrapRounds = 1000;
// Per-object figures need this many probes of a kind: below it the interval is too wide to
// say anything about one object.
constexpr size_t kMinProbesPerObject = 8;
// The probes' streams: the bake's seed mixed with this, so that they never repeat the bake's
// own paths (which would hide the path tracer's noise from its estimate).
constexpr uint64_t kProbeStreamSalt = 0xE1A5E57Au;


// What one probe contributes to the estimate.
struct ProbeRecord {
  double difference = 0.0;  // Y(baked) - Y(path traced)
  double variance = 0.0;    // of the path-traced luminance mean
  double reference = 0.0;   // Y(path traced)
  double weight = 1.0;      // the probe's sampling weight (error_probes.h)
  uint32_t object_id = 0;
};

// Weighted means over the probes estimate means over the points they were drawn from.
double nrmse_of(const std::vector<const ProbeRecord*>& records) {
  double squared = 0.0, reference = 0.0, weights = 0.0;
  for (const ProbeRecord* r : records) {
    squared += r->weight * (r->difference * r->difference - r->variance);
    reference += r->weight * r->reference;
    weights += r->weight;
  }
  if (!(reference > 0.0) || !(weights > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return std::sqrt(std::max(squared / weights, 0.0)) / (reference / weights);
}

ProbeErrorStatistics statistics_of(const std::vector<const ProbeRecord*>& records,
                                   uint64_t seed) {
  ProbeErrorStatistics s;
  s.probes = records.size();
  if (records.empty()) return s;
  double variance = 0.0, reference = 0.0, weights = 0.0;
  for (const ProbeRecord* r : records) {
    variance += r->weight * r->variance;
    reference += r->weight * r->reference;
    weights += r->weight;
  }
  const double n = weights > 0.0 ? weights : 1.0;
  s.mean_reference = reference / n;
  s.probe_noise = s.mean_reference > 0.0 ? std::sqrt(variance / n) / s.mean_reference
                                         : std::numeric_limits<double>::quiet_NaN();
  s.nrmse = nrmse_of(records);
  if (!std::isfinite(s.nrmse)) {
    s.low = s.high = s.nrmse;
    return s;
  }
  // Percentile bootstrap over the probes.
  Pcg32 rng(mix64(seed ^ 0xB0075u), 0x3C6EF372FE94F82Bull);
  std::vector<double> rounds;
  rounds.reserve(kBootstrapRounds);
  std::vector<const ProbeRecord*> resample(records.size());
  for (int b = 0; b < kBootstrapRounds; ++b) {
    for (auto& r : resample) {
      const uint64_t draw = (uint64_t(rng.next_uint()) << 32) | rng.next_uint();
      r = records[size_t(draw % records.size())];
    }
    const double value = nrmse_of(resample);
    if (std::isfinite(value)) rounds.push_back(value);
  }
  if (rounds.empty()) {
    s.low = s.high = s.nrmse;
    return s;
  }
  std::sort(rounds.begin(), rounds.end());
  auto quantile = [&](double q) {
    return rounds[std::min(rounds.size() - 1, size_t(q * double(rounds.size())))];
  };
  s.low = quantile(0.05);
  s.high = quantile(0.95);
  return s;
}

// Path-traces every probe and pairs it with the bake's value there.
std::vector<ProbeRecord> trace_probes(const DirectLight& direct, const ErrorProbes& probes,
                                      const std::vector<glm::vec3>& baked,
                                      const ErrorEstimateSettings& settings, uint64_t first_index,
                                      std::atomic<uint64_t>& done, double total,
                                      std::atomic<uint64_t>& rays, JobContext& context) {
  std::vector<ProbeRecord> records(probes.size());
  const int64_t samples = settings.samples;
  const uint64_t seed = mix64(settings.seed ^ kProbeStreamSalt);
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, probes.size(), 2),
      [&](const tbb::blocked_range<size_t>& block) {
        uint64_t local_rays = 0;
        for (size_t i = block.begin(); i != block.end(); ++i) {
          const glm::vec3 n = probes.points.normals[i];
          const SurfacePoint x{probes.points.positions[i], n, n};
          glm::dvec3 sum(0.0);
          double sum_y = 0.0, sum_y2 = 0.0;
          for (int64_t first = 0; first < samples; first += kSamplesPerCheck) {
            context.throw_if_cancelled();
            const int64_t last = std::min(samples, first + kSamplesPerCheck);
            for (int64_t s = first; s < last; ++s) {
              RandomStream rng = sample_stream(seed, first_index + i, uint64_t(s));
              const glm::vec3 value =
                  sample_indirect(direct, x, rng, settings.max_bounces, local_rays);
              if (!(std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z))) {
                continue;  // counted as a zero sample, as the path tracer drops it
              }
              const double y = luminance(glm::dvec3(value));
              sum += glm::dvec3(value);
              sum_y += y;
              sum_y2 += y * y;
            }
            const uint64_t finished =
                done.fetch_add(uint64_t(last - first), std::memory_order_relaxed) +
                uint64_t(last - first);
            context.set_stage_progress(double(finished) / total);
          }
          const double count = double(samples);
          const double mean_y = sum_y / count;
          const double sample_variance =
              samples > 1 ? std::max(sum_y2 - count * mean_y * mean_y, 0.0) / (count - 1.0) : 0.0;
          ProbeRecord& r = records[i];
          r.reference = luminance(sum / count);
          r.difference = luminance(glm::dvec3(probes.baked_value(i, baked))) - r.reference;
          r.variance = sample_variance / count;
          r.weight = double(probes.sampling_weight(i));
          r.object_id = probes.points.object_ids[i];
        }
        rays.fetch_add(local_rays, std::memory_order_relaxed);
      },
      tbb::simple_partitioner());
  return records;
}

std::vector<const ProbeRecord*> pointers(const std::vector<ProbeRecord>& records) {
  std::vector<const ProbeRecord*> out;
  out.reserve(records.size());
  for (const ProbeRecord& r : records) out.push_back(&r);
  return out;
}

std::map<uint32_t, std::vector<const ProbeRecord*>> by_object(
    const std::vector<ProbeRecord>& records) {
  std::map<uint32_t, std::vector<const ProbeRecord*>> groups;
  for (const ProbeRecord& r : records) groups[r.object_id].push_back(&r);
  return groups;
}

std::string statistics_json(const ProbeErrorStatistics& s) {
  return "{\"probes\": " + std::to_string(s.probes) + ", \"nrmse\": " + json_number(s.nrmse) +
         ", \"interval\": [" + json_number(s.low) + ", " + json_number(s.high) +
         "], \"mean_reference\": " + json_number(s.mean_reference) +
         ", \"probe_noise\": " + json_number(s.probe_noise) + "}";
}

}  // namespace

ErrorEstimate estimate_error(const DirectLight& direct, const ErrorProbes& at_points,
                             const ErrorProbes& display, const std::vector<glm::vec3>& baked,
                             const ErrorEstimateSettings& settings, JobContext& context) {
  ErrorEstimate estimate;
  estimate.samples = settings.samples;
  const double total = double(at_points.size() + display.size()) * double(settings.samples);
  std::atomic<uint64_t> done{0}, rays{0};
  context.set_stage_text("estimating the error: " +
                         std::to_string(at_points.size() + display.size()) + " probes x " +
                         std::to_string(settings.samples) + " paths");
  const std::vector<ProbeRecord> point_records =
      trace_probes(direct, at_points, baked, settings, 0, done, total, rays, context);
  const std::vector<ProbeRecord> display_records = trace_probes(
      direct, display, baked, settings, at_points.size(), done, total, rays, context);
  estimate.rays = rays.load();

  estimate.at_points = statistics_of(pointers(point_records), settings.seed);
  estimate.display = statistics_of(pointers(display_records), settings.seed + 1);
  const auto point_groups = by_object(point_records);
  const auto display_groups = by_object(display_records);
  std::map<uint32_t, ObjectErrorEstimate> objects;
  for (const auto& [id, group] : point_groups) {
    if (group.size() < kMinProbesPerObject) continue;
    objects[id].object_id = id;
    objects[id].at_points = statistics_of(group, settings.seed + 2 + id);
  }
  for (const auto& [id, group] : display_groups) {
    if (group.size() < kMinProbesPerObject) continue;
    objects[id].object_id = id;
    objects[id].display = statistics_of(group, settings.seed + 3 + id);
  }
  for (const auto& [id, object] : objects) estimate.objects.push_back(object);
  return estimate;
}

std::string error_estimate_json(const ErrorEstimate& estimate) {
  std::string objects = "[";
  for (const ObjectErrorEstimate& o : estimate.objects) {
    if (objects.size() > 1) objects += ", ";
    objects += "{\"object\": " + std::to_string(o.object_id) +
               ", \"at_points\": " + statistics_json(o.at_points) +
               ", \"display\": " + statistics_json(o.display) + "}";
  }
  objects += "]";
  return "{\"samples\": " + std::to_string(estimate.samples) +
         ", \"rays\": " + std::to_string(estimate.rays) +
         ", \"at_points\": " + statistics_json(estimate.at_points) +
         ", \"display\": " + statistics_json(estimate.display) + ", \"objects\": " + objects + "}";
}

}  // namespace bakegi
