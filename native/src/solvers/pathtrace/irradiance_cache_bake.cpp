#include "solvers/pathtrace/irradiance_cache_bake.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "scene/scene.h"
#include "solvers/adaptive_sampling.h"
#include "solvers/pathtrace/indirect_path.h"
#include "solvers/pathtrace/irradiance_cache.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/luminance.h"
#include "util/random.h"
#include "util/report.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

// Records are at most this fraction of the scene's extent (its bounding box's diagonal) wide:
// a gather that sees only the sky or far walls says little about light that changes on a
// smaller scale.
constexpr float kMaxRadiusOfExtent = 0.25f;
// The pilot's random numbers are a different sequence from the gathers'.
constexpr uint64_t kPilotSeedSalt = 0x51f15e11ull;
// Cancel is checked every this many samples of a gather.
constexpr int64_t kSamplesPerCheck = 32;

SurfacePoint surface_of(const BakePoints& points, size_t i) {
  return {points.positions[i], points.normals[i], points.normals[i]};
}

// Step 1: the harmonic mean distance of kPilotRays cosine rays from every point.
std::vector<float> pilot_radii(const DirectLight& direct, const BakePoints& points,
                               const IrradianceCacheSettings& settings, float max_radius,
                               JobContext& context) {
  std::vector<float> radii(points.size());
  std::atomic<size_t> done{0};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, points.size(), 64),
      [&](const tbb::blocked_range<size_t>& block) {
        context.throw_if_cancelled();
        uint64_t rays = 0;
        for (size_t i = block.begin(); i != block.end(); ++i) {
          const SurfacePoint x = surface_of(points, i);
          const Frame frame(x.shading_normal);
          const glm::vec3 origin = direct.ray_origin(x);
          double inverse_sum = 0.0;
          for (int s = 0; s < kPilotRays; ++s) {
            RandomStream rng =
                sobol_sample_stream(uint64_t(settings.seed) ^ kPilotSeedSalt, i, uint64_t(s));
            const float u1 = rng.next_float(), u2 = rng.next_float();
            const glm::vec3 d = frame.to_world(HemisphereCells::local_direction(u1, u2));
            const Hit hit = direct.tracer().intersect(Ray{origin, d, 0.0f, 1e30f});
            ++rays;
            if (hit.hit && hit.t > 0.0f) inverse_sum += 1.0 / double(hit.t);
          }
          radii[i] = inverse_sum > 0.0 ? std::min(max_radius, float(kPilotRays / inverse_sum))
                                       : max_radius;
        }
        context.report().add_count("rays", rays);
        const size_t now = done.fetch_add(block.size()) + block.size();
        context.set_stage_progress(0.05 * double(now) / double(points.size()));
      });
  return radii;
}

// Step 3: one record's gather of samples [from, to), its gradients as measured.
IrradianceGather gather_at(const DirectLight& direct, const BakePoints& points, size_t i,
                           const IrradianceCacheSettings& settings, int64_t from, int64_t to,
                           uint64_t& rays, uint64_t& dropped, JobContext& context) {
  const SurfacePoint x = surface_of(points, i);
  const Frame frame(x.shading_normal);
  const glm::vec3 origin = direct.ray_origin(x);
  HemisphereCells cells;
  for (int64_t first = from; first < to; first += kSamplesPerCheck) {
    context.throw_if_cancelled();
    const int64_t last = std::min(to, first + kSamplesPerCheck);
    for (int64_t s = first; s < last; ++s) {
      RandomStream rng =
          sobol_sample_stream(uint64_t(settings.seed), i, uint64_t(settings.sample_offset + s));
      const float u1 = rng.next_float(), u2 = rng.next_float();
      const glm::vec3 d = frame.to_world(HemisphereCells::local_direction(u1, u2));
      ++rays;
      const Hit hit = direct.tracer().intersect(Ray{origin, d, 0.0f, 1e30f});
      if (!hit.hit) {
        cells.add(u1, u2, glm::vec3(0.0f), std::numeric_limits<float>::infinity());
        continue;
      }
      const PathRadiance path =
          trace_from_first_hit(direct, hit, d, rng, settings.max_bounces, rays);
      glm::vec3 radiance = path.first_light + path.rest;
      // A non-finite sample counts as 0 (and is reported), as in the plain path tracer.
      if (!is_finite(radiance)) {
        radiance = glm::vec3(0.0f);
        ++dropped;
      }
      cells.add(u1, u2, radiance, hit.t);
    }
  }
  return cells.estimate(frame);
}

// A fixed pseudo-random order of the points (step 2).
std::vector<uint32_t> shuffled_order(size_t count, uint64_t seed) {
  std::vector<uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<uint64_t> keys(count);
  for (size_t i = 0; i < count; ++i) {
    uint64_t h =
        (uint64_t(i) + 1) * 0x9e3779b97f4a7c15ull ^ (uint64_t(seed) * 0xbf58476d1ce4e5b9ull);
    h ^= h >> 31;
    h *= 0x94d049bb133111ebull;
    keys[i] = h ^ (h >> 29);
  }
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return keys[a] < keys[b] || (keys[a] == keys[b] && a < b);
  });
  return order;
}

}  // namespace

bool bake_with_irradiance_cache(const DirectLight& direct, const BakePoints& points,
                                const IrradianceCacheSettings& settings, std::span<glm::vec3> out,
                                std::span<float> variance_of_mean, JobContext& context) {
  const size_t count = points.size();
  if (out.size() != count || (!variance_of_mean.empty() && variance_of_mean.size() != count)) {
    throw Error(BAKEGI_ERROR_INTERNAL, "output size does not match the number of bake points");
  }
  if (count == 0) return true;
  Report& report = context.report();
  const float extent = direct.scene().extent();
  const float max_radius = extent > 0.0f ? kMaxRadiusOfExtent * extent : 1.0f;
  // The index's finest cells: reaches below this share them (only the lookup's speed).
  const float smallest_radius = max_radius * std::ldexp(1.0f, -20);

  context.set_stage_progress(0.0);
  context.set_stage_text("irradiance cache: measuring distances at " + std::to_string(count) +
                         " points");
  const std::vector<float> pilot = pilot_radii(direct, points, settings, max_radius, context);

  std::vector<IrradianceRecord> records;   // their gathers' gradients shrunk
  std::vector<IrradianceGather> measured;  // the same gathers as measured (to add to)
  std::vector<uint32_t> record_point;      // the bake point of each record
  // With a target error, records start with the least their cells need and rounds add
  // samples where the noise is (as solvers/adaptive_sampling.h does for points).
  const bool adaptive = settings.target_error > 0.0;
  const int64_t first_samples =
      adaptive ? std::min(settings.samples, kIrradianceCacheMinSamples) : settings.samples;
  std::vector<uint32_t> record_of(count, UINT32_MAX);  // each point's record, if it is one
  const std::vector<uint32_t> order = shuffled_order(count, uint64_t(settings.seed));
  std::vector<uint32_t> uncovered = order;
  std::atomic<uint64_t> dropped{0};
  // The records as they stand: placement adds new ones to it with their pilot radii; after
  // each gather it is made again with the gathered radii (a record's reach is its key in
  // the index) and serves the next round's placement, the coverage test and interpolation.
  IrradianceCache cache(settings.accuracy, smallest_radius);
  const auto rebuild_cache = [&] {
    cache = IrradianceCache(settings.accuracy, smallest_radius);
    for (const IrradianceRecord& r : records) cache.add(r);
  };
  int rounds = 0;
  double slice = 0.9;
  for (int round = 0; round < kIrradianceCacheRounds && !uncovered.empty(); ++round) {
    ++rounds;
    // Placement: against the records so far (their radii from their gathers) and the new
    // ones (their pilot radii).
    const size_t first_new = records.size();
    const bool last_round = round + 1 == kIrradianceCacheRounds;
    for (const uint32_t i : uncovered) {
      const glm::vec3& x = points.positions[i];
      const glm::vec3& n = points.normals[i];
      if (!last_round && cache.covers(x, n, pilot[i])) continue;
      IrradianceRecord r;
      r.position = x;
      r.normal = n;
      r.radius = pilot[i];
      cache.add(r);
      record_of[i] = uint32_t(records.size());
      records.push_back(r);
      measured.emplace_back();
      record_point.push_back(i);
    }
    const size_t new_records = records.size() - first_new;
    if (round == 0) {
      const double fraction = double(new_records) / double(count);
      report.set_number("irradiance_cache_record_fraction", fraction);
      if (fraction > kMaxRecordFraction) {
        report.warn("irradiance cache not used: " + std::to_string(int(100.0 * fraction + 0.5)) +
                    "% of the bake points would be records (it pays off below " +
                    std::to_string(int(100.0 * kMaxRecordFraction)) +
                    "%: the points are not dense for their surroundings); every point traces "
                    "its own paths");
        report.add_count("irradiance_cache_declined", 1);
        return false;
      }
    }
    context.set_stage_text("irradiance cache: gathering " + std::to_string(first_samples) +
                           " paths at " + std::to_string(new_records) + " records (round " +
                           std::to_string(round + 1) + ")");
    std::atomic<size_t> gathered{0};
    const double progress_from = 1.0 - slice;
    const double progress_to = 1.0 - slice / 2.0;
    tbb::parallel_for(
        tbb::blocked_range<size_t>(first_new, records.size(), 1),
        [&](const tbb::blocked_range<size_t>& block) {
          uint64_t rays = 0, block_dropped = 0;
          for (size_t r = block.begin(); r != block.end(); ++r) {
            IrradianceRecord& record = records[r];
            measured[r] = gather_at(direct, points, record_point[r], settings, 0, first_samples,
                                    rays, block_dropped, context);
            record.gather = shrink_gradients(measured[r]);
            record.radius = record_radius(record.gather, max_radius);
            const size_t now = gathered.fetch_add(1) + 1;
            context.set_stage_progress(progress_from + (progress_to - progress_from) * double(now) /
                                                           double(new_records));
          }
          report.add_count("rays", rays);
          if (block_dropped) dropped.fetch_add(block_dropped);
        },
        tbb::simple_partitioner());
    slice /= 2.0;

    // What the records with their gathered radii leave uncovered.
    rebuild_cache();
    std::vector<uint8_t> left(count, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, uncovered.size(), 256),
                      [&](const tbb::blocked_range<size_t>& block) {
                        for (size_t k = block.begin(); k != block.end(); ++k) {
                          const uint32_t i = uncovered[k];
                          if (record_of[i] != UINT32_MAX) continue;
                          left[k] = !cache.covers(points.positions[i], points.normals[i], pilot[i]);
                        }
                      });
    std::vector<uint32_t> still;
    for (size_t k = 0; k < uncovered.size(); ++k) {
      if (left[k]) still.push_back(uncovered[k]);
    }
    uncovered.swap(still);
  }

  // With a target error: rounds of more samples at the records whose noise needs them. The
  // prediction is over the records, an upper bound for the points between them (each a
  // weighted mean of several). Radii, and so which records a point uses, stay as placed.
  if (adaptive) {
    int sampling_rounds = 1;
    std::vector<PointTally> tallies(records.size());
    for (;;) {
      for (size_t r = 0; r < records.size(); ++r) {
        tallies[r] = {measured[r].samples, measured[r].luminance_sum,
                      measured[r].luminance_squares};
      }
      const SamplingRound next =
          plan_sampling_round(tallies, settings.target_error, settings.samples);
      report.set_number("sampling_predicted_error", next.predicted_error);
      if (next.done()) break;
      ++sampling_rounds;
      // Whole blocks of 2^8 samples keep every gradient cell stratified.
      std::vector<int64_t> added(records.size());
      for (size_t r = 0; r < records.size(); ++r) {
        const int64_t blocks =
            (next.added[r] + kIrradianceCacheMinSamples - 1) / kIrradianceCacheMinSamples;
        added[r] =
            std::min(blocks * kIrradianceCacheMinSamples, settings.samples - measured[r].samples);
      }
      context.set_stage_text("irradiance cache: more paths at the records towards " +
                             std::to_string(settings.target_error * 100.0) + "% error");
      tbb::parallel_for(
          tbb::blocked_range<size_t>(0, records.size(), 1),
          [&](const tbb::blocked_range<size_t>& block) {
            uint64_t rays = 0, block_dropped = 0;
            for (size_t r = block.begin(); r != block.end(); ++r) {
              if (added[r] <= 0) continue;
              const int64_t from = measured[r].samples;
              measured[r] = combine_gathers(
                  measured[r], gather_at(direct, points, record_point[r], settings, from,
                                         from + added[r], rays, block_dropped, context));
              const float radius = records[r].radius;
              records[r].gather = shrink_gradients(measured[r]);
              records[r].radius = radius;
            }
            report.add_count("rays", rays);
            if (block_dropped) dropped.fetch_add(block_dropped);
          },
          tbb::simple_partitioner());
      context.set_stage_progress(1.0 - slice / 2.0);
      slice /= 2.0;
    }
    report.add_count("sampling_rounds", uint64_t(sampling_rounds));
    report.set_number("target_error", settings.target_error);
  }

  // Interpolation everywhere else, and the leave-one-out check at the records.
  context.set_stage_text("irradiance cache: interpolating " +
                         std::to_string(count - records.size()) + " points from " +
                         std::to_string(records.size()) + " records");
  if (adaptive) rebuild_cache();  // the rounds changed the records' values
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256),
                    [&](const tbb::blocked_range<size_t>& block) {
                      context.throw_if_cancelled();
                      for (size_t i = block.begin(); i != block.end(); ++i) {
                        float variance = 0.0f;
                        if (record_of[i] != UINT32_MAX) {
                          const IrradianceGather& g = records[record_of[i]].gather;
                          out[i] = g.value;
                          variance = g.luminance_variance_of_mean;
                        } else {
                          const IrradianceCache::Interpolated v =
                              cache.interpolate(points.positions[i], points.normals[i], pilot[i]);
                          out[i] = v.value;
                          variance = v.luminance_variance_of_mean;
                        }
                        if (!variance_of_mean.empty()) variance_of_mean[i] = variance;
                      }
                    });
  double squares = 0.0, noise = 0.0, mean = 0.0;
  size_t checked = 0;
  for (size_t r = 0; r < records.size(); ++r) {
    const IrradianceCache::Interpolated v =
        cache.interpolate(records[r].position, records[r].normal,
                          std::min(records[r].radius, pilot[record_point[r]]), uint32_t(r));
    if (!v.covered) continue;
    const double d = luminance(v.value) - luminance(records[r].gather.value);
    squares += d * d;
    noise += double(v.luminance_variance_of_mean) + records[r].gather.luminance_variance_of_mean;
    ++checked;
  }
  for (size_t i = 0; i < count; ++i) mean += luminance(out[i]);
  mean /= double(count);
  report.add_count("irradiance_cache_records", records.size());
  report.add_count("irradiance_cache_rounds", uint64_t(rounds));
  uint64_t samples = 0;
  for (const IrradianceGather& g : measured) samples += uint64_t(g.samples);
  report.add_count("samples", samples);
  report.add_count("irradiance_cache_checked_records", checked);
  if (checked > 0 && mean > 0.0) {
    const double interpolation = std::sqrt(std::max(0.0, squares - noise) / double(checked)) / mean;
    report.set_number("irradiance_cache_interpolation_error", interpolation);
    // A target's prediction covers the records' noise; what interpolation adds comes on top.
    if (adaptive) {
      const double noise_only = report.number("sampling_predicted_error");
      report.set_number("sampling_predicted_error",
                        std::sqrt(noise_only * noise_only + interpolation * interpolation));
    }
    if (interpolation > kWarnInterpolationError) {
      report.warn("the irradiance cache's interpolation may add about " +
                  std::to_string(int(100.0 * interpolation + 0.5)) +
                  "% error (records predicted from their neighbours); a smaller "
                  "irradiance_cache accuracy places records closer");
    }
  }
  if (dropped.load() > 0) {
    report.warn(std::to_string(dropped.load()) + " non-finite Monte Carlo samples were dropped");
  }
  context.set_stage_progress(1.0);
  return true;
}

}  // namespace bakegi
