// The path tracer through an irradiance cache (irradiance_cache.h): gathers at the records,
// interpolation elsewhere.
//
// 1. Every bake point's radius is estimated from a pilot of kPilotRays cosine rays (the
//    harmonic mean of their hit distances; closest hits only, no shading).
// 2. Records are placed greedily, the points in a fixed pseudo-random order: a point no
//    record covers becomes one. Visiting the points shuffled spreads the records like a
//    Poisson-disk pattern, not in scan lines.
// 3. Each record gathers `samples` paths (at least 2^8: the gradient cells,
//    irradiance_gradients.h), path for path the path tracer's for that point with its
//    first direction stratified by the cells; its radius is then set from the gather.
// 4. Where a record's radius came out smaller than its pilot said, points may be left
//    uncovered: they are placed and gathered again, up to kRounds rounds, the last of which
//    makes every uncovered point a record.
// 5. With a target error, rounds add paths to the records whose noise needs them (whole
//    blocks of 2^8, so every block stratifies the cells), until the noise the records' spread
//    predicts meets the target; placement and radii stay.
// 6. Every other point is interpolated.
// A point's pilot radius also bounds which records it may use (irradiance_cache.h: R_x), and
// placement and the rounds test coverage with it: on Sponza, without it, vertices enclosed by
// other geometry (no light reaches them) took the light of records beside them in the open.
// The report says how many records there were, and a leave-one-out estimate of the error
// that interpolation adds: each record predicted from the others where they cover it, the
// records' noise taken out (irradiance_cache_interpolation_error, relative to the mean); it
// warns above kWarnInterpolationError. Where the first placement makes more than
// kMaxRecordFraction of the points records, the cache declines (with a warning): the points
// are not dense for their surroundings and the plain path tracer is as fast.
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "scene/bake_points.h"
#include "solvers/pathtrace/irradiance_cache.h"

namespace bakegi {

class DirectLight;
class JobContext;

struct IrradianceCacheSettings {
  float accuracy = 0.2f;  // a
  int64_t samples = 1024;
  int64_t seed = 0;
  int64_t sample_offset = 0;
  int max_bounces = 64;
  // > 0: records start with kIrradianceCacheMinSamples paths and rounds add more where their
  // noise is until the noise predicted over the records meets it (`samples` caps a record).
  double target_error = 0.0;
};

inline constexpr int kPilotRays = 32;
inline constexpr int kIrradianceCacheRounds = 4;
inline constexpr int64_t kIrradianceCacheMinSamples = 256;
// Above this fraction of records the cache saves at most 2x the paths, less its pilot and
// rounds: measured on Sponza's vertices (69-76% records) it gained nothing at equal error.
inline constexpr double kMaxRecordFraction = 0.5;
// The leave-one-out estimate above which the report warns (the "Good" quality's 5%).
inline constexpr double kWarnInterpolationError = 0.05;
// Bytes per bake point, for the job's memory estimate: per point the pilot radius, its
// record, the shuffled order and its keys, the coverage lists; per record (at most
// kMaxRecordFraction of the points: the cache declines beyond) the record in the list and
// in the cache (twice while it is made again), its gather as measured, its point and index
// entry.
inline constexpr size_t kIrradianceCacheBytesPerPoint =
    4 + 4 + 4 + 8 + 4 + 1 +
    (3 * sizeof(IrradianceRecord) + sizeof(IrradianceGather) + 4 + 3 * 16) / 2;

// false: declined (nothing written) because the first placement made more than
// kMaxRecordFraction of the points records; the caller then bakes every point.
bool bake_with_irradiance_cache(const DirectLight& direct, const BakePoints& points,
                                const IrradianceCacheSettings& settings, std::span<glm::vec3> out,
                                std::span<float> variance_of_mean, JobContext& context);

}  // namespace bakegi
