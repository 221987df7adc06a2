#include "solvers/meshless/point_placement.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <unordered_map>

#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::meshless {

namespace {

// Candidates the pilot run traces to measure the reachable area and extent. Enough that
// every surface larger than ~1/1000 of the total gets hit many times; smaller triangles
// missed by the pilot only lower the (already approximate) estimate a little.
constexpr size_t kPilotCandidates = size_t(1) << 15;
// §2.3: rays of length 3R; candidates with a harmonic mean distance below R / 6 are rejected.
constexpr float kHarmonicRayLength = 3.0f;
constexpr float kHarmonicThreshold = 1.0f / 6.0f;
// Random sequential adsorption of disks in the plane jams at this coverage (Feder 1980).
constexpr double kJammingCoverage = 0.547;
constexpr uint32_t kMaxLevels = 16;
// Automatic defaults (see the header): R_coarse = 0.36 l (n / 17.8)^(1/6), n = A / l^2; four
// levels, the finest >= l / 60.
constexpr double kCoarseSpacingPerFreePath = 0.36;
constexpr double kCornellBoxAreaOverFreePathSquared = 17.8;
constexpr uint32_t kAutomaticLevels = 4;
constexpr float kFinestSpacingPerFreePath = 1.0f / 60.0f;

constexpr uint64_t kPilotSalt = 0x5EED'0001'0000'0000ull;
constexpr uint64_t kLevelSalt = 0x5EED'0002'0000'0000ull;
constexpr uint64_t kHarmonicSalt = 0x5EED'0003'0000'0000ull;
constexpr uint64_t kFreePathSalt = 0x5EED'0004'0000'0000ull;
// Rays for the mean free path: its relative noise is about the chord lengths' spread (~0.7 of
// the mean in a box) over sqrt(4096), ~1%.
constexpr size_t kFreePathRays = 4096;

using ParticleFactory = std::function<ImportanceParticles(uint64_t seed)>;

// Points of one level bucketed in cubic cells of side R: since D >= Euclidean distance
// (weight_function.h), every point within D < R of a query lies in the 27 cells around it.
class HashGrid {
 public:
  explicit HashGrid(float cell) : inverse_cell_(1.0f / cell) {}

  void insert(uint32_t index, const glm::vec3& position) {
    const glm::ivec3 c = cell_of(position);
    cells_[key(c.x, c.y, c.z)].push_back(index);
  }

  // True if `conflict(index)` holds for some point in the cells around `position`.
  template <class Conflict>
  bool any_near(const glm::vec3& position, Conflict&& conflict) const {
    const glm::ivec3 c = cell_of(position);
    for (int dz = -1; dz <= 1; ++dz) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key(c.x + dx, c.y + dy, c.z + dz));
          if (it == cells_.end()) continue;
          for (uint32_t index : it->second) {
            if (conflict(index)) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  glm::ivec3 cell_of(const glm::vec3& p) const { return glm::ivec3(glm::floor(p * inverse_cell_)); }
  // 21 bits per axis: cells 2^21 apart share a bucket, which costs a few extra distance
  // tests and never a wrong answer.
  static uint64_t key(int x, int y, int z) {
    constexpr uint64_t mask = (uint64_t(1) << 21) - 1;
    return (uint64_t(uint32_t(x)) & mask) | ((uint64_t(uint32_t(y)) & mask) << 21) |
           ((uint64_t(uint32_t(z)) & mask) << 42);
  }

  float inverse_cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// §2.3: the harmonic mean of the distances to the geometry over the candidate's hemisphere,
// rays of length `max_distance` (misses count as max_distance). Directions are uniform in
// solid angle (as Ward's irradiance-cache radius), jittered on a side x side grid over
// (cos theta, phi): stratification keeps the estimate stable with few rays.
float harmonic_mean_distance(const RayTracer& tracer, const Candidate& candidate,
                             float max_distance, uint32_t side, float epsilon, RandomStream& random,
                             uint64_t& rays) {
  const Frame frame(candidate.geometric_normal);
  const glm::vec3 origin = candidate.position + candidate.geometric_normal * epsilon;
  double inverse_sum = 0.0;
  for (uint32_t i = 0; i < side; ++i) {
    for (uint32_t j = 0; j < side; ++j) {
      const float cos_theta = (float(i) + random.next_float()) / float(side);
      const float phi = 2.0f * kPi * (float(j) + random.next_float()) / float(side);
      const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
      const glm::vec3 direction = frame.to_world(
          glm::vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
      const Hit hit = tracer.intersect(Ray{origin, direction, 0.0f, max_distance});
      const float distance = hit.hit ? std::max(hit.t, epsilon) : max_distance;
      inverse_sum += 1.0 / double(distance);
    }
  }
  rays += uint64_t(side) * side;
  return float(double(side) * side / inverse_sum);
}

struct Pilot {
  double area = 0.0;
  float extent = 0.0f;
  float mean_free_path = 0.0f;
  uint64_t rays = 0;
};

// The mean distance a cosine-distributed ray from the pilot candidates travels to the next
// surface (misses, in an open scene, count as the extent): the scene's own length, 4V/S in a
// closed convex room (Cauchy), about a room's size in a building, shorter among furniture.
// One ray from each of `kFreePathRays` candidates spread over the batch.
float mean_free_path(const RayTracer& tracer, const std::vector<Candidate>& candidates,
                     float extent, float epsilon, uint64_t seed, uint64_t& rays) {
  RandomStream random(mix64(seed ^ kFreePathSalt), 0);
  const size_t stride = std::max<size_t>(1, candidates.size() / kFreePathRays);
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < candidates.size(); i += stride) {
    const Candidate& c = candidates[i];
    const float u1 = random.next_float(), u2 = random.next_float();
    const glm::vec3 direction =
        Frame(c.geometric_normal).to_world(sample_cosine_hemisphere(u1, u2));
    const glm::vec3 origin = c.position + c.geometric_normal * epsilon;
    const Hit hit = tracer.intersect(Ray{origin, direction, 0.0f, extent});
    sum += hit.hit ? double(hit.t) : double(extent);
    ++count;
  }
  rays += count;
  return count > 0 ? float(sum / double(count)) : 0.0f;
}

// A first batch of candidates from a separate stream: which triangles are reachable (their
// area), how far apart the reachable surfaces are (the bounding box diagonal) and how far
// light travels between them (the mean free path).
Pilot run_pilot(const Scene& scene, const RayTracer& tracer, const ParticleFactory& particles,
                uint64_t seed, JobContext& context) {
  ImportanceParticles pilot_particles = particles(mix64(seed ^ kPilotSalt));
  std::vector<Candidate> candidates;
  while (candidates.size() < kPilotCandidates) {
    context.throw_if_cancelled();
    pilot_particles.next_batch(candidates);
  }
  std::vector<bool> reached(scene.triangles.size(), false);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const Candidate& c : candidates) {
    reached[c.triangle] = true;
    lo = glm::min(lo, c.position);
    hi = glm::max(hi, c.position);
  }
  Pilot pilot;
  for (size_t t = 0; t < reached.size(); ++t) {
    if (reached[t]) pilot.area += scene.triangles[t].area;
  }
  pilot.extent = glm::length(hi - lo);
  pilot.rays = pilot_particles.rays_traced();
  context.throw_if_cancelled();
  pilot.mean_free_path = mean_free_path(tracer, candidates, pilot.extent,
                                        placement_ray_epsilon(scene), seed, pilot.rays);
  // Every candidate on one point (a degenerate scene): a length from the area instead.
  if (!(pilot.mean_free_path > 0.0f)) pilot.mean_free_path = float(std::sqrt(pilot.area));
  return pilot;
}

void check_settings(const PlacementSettings& s) {
  auto fail = [](const std::string& what) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless placement: " + what);
  };
  if (!std::isfinite(s.coarse_spacing) || s.coarse_spacing < 0.0f) {
    fail("coarse spacing R_coarse must be finite and >= 0 (0 = automatic)");
  }
  if (s.levels > kMaxLevels) fail("at most " + std::to_string(kMaxLevels) + " levels");
  if (s.max_failures == 0) fail("max_failures must be at least 1");
  if (!(s.c_coarse > 0.0f) || !(s.c_fine > 0.0f) || !std::isfinite(s.c_coarse) ||
      !std::isfinite(s.c_fine)) {
    fail("support factors C must be positive");
  }
  if (s.harmonic_rays == 0) fail("harmonic_rays must be at least 1");
  if (s.max_points == 0) fail("max_points must be at least 1");
  if (s.particles.bounces <= s.particles.skipped_bounces) {
    fail("particles must bounce more often than the bounces they skip");
  }
}

std::string too_many_points_message(double estimate, uint64_t cap, float spacing, uint32_t levels) {
  std::ostringstream m;
  m << "meshless placement: about " << uint64_t(estimate) << " points estimated for " << levels
    << " level(s) from R_coarse = " << spacing << " m, more than the cap of " << cap
    << " (set by memory_budget_mb); use fewer levels or a larger coarse spacing, or raise the "
       "budget";
  return m.str();
}

std::vector<BasisPoint> place(const Scene& scene, const RayTracer& tracer,
                              const ParticleFactory& particles, const PlacementSettings& settings,
                              JobContext& context, PlacementStatistics* statistics_out) {
  check_settings(settings);
  PlacementStatistics statistics;
  const Pilot pilot = run_pilot(scene, tracer, particles, settings.seed, context);
  statistics.reachable_area = float(pilot.area);
  statistics.reachable_extent = pilot.extent;
  statistics.mean_free_path = pilot.mean_free_path;
  statistics.particle_rays = pilot.rays;

  const float coarse = settings.coarse_spacing > 0.0f
                           ? settings.coarse_spacing
                           : automatic_coarse_spacing(pilot.mean_free_path, float(pilot.area));
  uint32_t levels =
      settings.levels > 0 ? settings.levels : automatic_level_count(coarse, pilot.mean_free_path);

  auto total_estimate = [&](uint32_t level_count) {
    double total = 0.0;
    for (uint32_t l = 0; l < level_count; ++l) {
      total += estimated_point_count(pilot.area, coarse / float(1u << l));
    }
    return total;
  };
  if (settings.levels == 0) {
    while (levels > 1 && total_estimate(levels) > double(settings.max_points)) {
      --levels;
      statistics.levels_reduced = true;
    }
  }
  const double total = total_estimate(levels);
  if (total > double(settings.max_points)) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                too_many_points_message(total, settings.max_points, coarse, levels));
  }

  std::vector<BasisPoint> points;
  points.reserve(size_t(std::min(total * 1.25, double(settings.max_points))));
  const uint32_t side =
      std::max(1u, uint32_t(std::lround(std::sqrt(double(settings.harmonic_rays)))));
  const float epsilon = placement_ray_epsilon(scene);
  double estimate_done = 0.0;
  for (uint32_t level = 0; level < levels; ++level) {
    const float spacing = coarse / float(1u << level);
    const float c = levels == 1 ? settings.c_coarse
                                : settings.c_coarse + (settings.c_fine - settings.c_coarse) *
                                                          float(level) / float(levels - 1);
    LevelStatistics level_statistics;
    level_statistics.spacing = spacing;
    level_statistics.support_radius = c * spacing;
    const double level_estimate = estimated_point_count(pilot.area, spacing);
    level_statistics.estimated_points = uint64_t(level_estimate);

    // Each level draws its own candidates, so the levels are independent (§2.3).
    ImportanceParticles level_particles =
        particles(mix64(settings.seed ^ (kLevelSalt + uint64_t(level))));
    const size_t level_begin = points.size();
    HashGrid grid(spacing);
    std::vector<Candidate> batch;
    size_t next = 0;
    uint64_t harmonic_serial = 0;
    for (uint32_t failures = 0; failures < settings.max_failures;) {
      if (next == batch.size()) {
        context.throw_if_cancelled();
        const double placed = double(points.size() - level_begin);
        context.set_stage_progress(
            std::min(1.0, (estimate_done + std::min(placed, level_estimate)) / total));
        batch.clear();
        next = 0;
        level_particles.next_batch(batch);
      }
      const Candidate& candidate = batch[next++];
      ++level_statistics.candidates;
      const BasisPoint point{candidate.position, candidate.normal, c * spacing, level};
      const bool conflict = grid.any_near(point.position, [&](uint32_t index) {
        return poisson_distance(points[index], point) < spacing;
      });
      if (conflict) {
        ++failures;
        continue;
      }
      if (settings.harmonic_mean_rejection) {
        RandomStream random =
            sample_stream(settings.seed ^ kHarmonicSalt, level, harmonic_serial++);
        const float mean =
            harmonic_mean_distance(tracer, candidate, kHarmonicRayLength * spacing, side, epsilon,
                                   random, statistics.harmonic_mean_rays);
        if (mean < kHarmonicThreshold * spacing) {
          ++level_statistics.harmonic_rejections;
          ++failures;
          continue;
        }
      }
      if (points.size() >= settings.max_points) {
        throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                    "meshless placement: more than the cap of " +
                        std::to_string(settings.max_points) + " points on level " +
                        std::to_string(level) + " (the estimate was lower: curved or folded " +
                        "surfaces hold more points); use fewer levels or raise memory_budget_mb");
      }
      grid.insert(uint32_t(points.size()), point.position);
      points.push_back(point);
      failures = 0;
    }
    level_statistics.points = points.size() - level_begin;
    if (level_statistics.points == 0) {
      // Only possible when the harmonic mean test rejects every candidate; the basis needs
      // contiguous levels, so say why instead of returning a hole.
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "meshless placement: level " + std::to_string(level) +
                      " got no points: every reachable surface is closer than R / 6 = " +
                      std::to_string(kHarmonicThreshold * spacing) +
                      " m to other geometry; use a smaller coarse spacing");
    }
    statistics.particle_rays += level_particles.rays_traced();
    statistics.levels.push_back(level_statistics);
    estimate_done += level_estimate;
  }
  context.set_stage_progress(1.0);
  if (statistics_out) *statistics_out = std::move(statistics);
  return points;
}

}  // namespace

float automatic_coarse_spacing(float mean_free_path, float reachable_area) {
  const double l = double(mean_free_path);
  const double n = double(reachable_area) / (l * l);
  return float(kCoarseSpacingPerFreePath * l *
               std::pow(std::max(n, 1e-6) / kCornellBoxAreaOverFreePathSquared, 1.0 / 6.0));
}

uint32_t automatic_level_count(float coarse_spacing, float mean_free_path) {
  const float finest = kFinestSpacingPerFreePath * mean_free_path;
  uint32_t levels = kAutomaticLevels;
  while (levels > 1 && coarse_spacing / float(1u << (levels - 1)) < finest) --levels;
  return levels;
}

double estimated_point_count(double area, double spacing) {
  return kJammingCoverage * area / (kPi * 0.25 * spacing * spacing);
}

std::vector<BasisPoint> place_points(const Scene& scene, const RayTracer& tracer,
                                     const glm::vec3& viewpoint, const PlacementSettings& settings,
                                     JobContext& context, PlacementStatistics* statistics) {
  const ParticleFactory particles = [&](uint64_t seed) {
    ParticleSettings particle_settings = settings.particles;
    particle_settings.seed = seed;
    return ImportanceParticles(scene, tracer, viewpoint, particle_settings);
  };
  return place(scene, tracer, particles, settings, context, statistics);
}

std::vector<BasisPoint> place_points(const Scene& scene, const RayTracer& tracer,
                                     const BakePoints& surfaces, const PlacementSettings& settings,
                                     JobContext& context, PlacementStatistics* statistics) {
  // Validate the sources once, not per level (the factory copies them each time).
  if (surfaces.size() == 0 || surfaces.normals.size() != surfaces.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "meshless placement: no source points to start importance particles from");
  }
  const ParticleFactory particles = [&](uint64_t seed) {
    ParticleSettings particle_settings = settings.particles;
    particle_settings.seed = seed;
    return ImportanceParticles(scene, tracer, surfaces, particle_settings);
  };
  return place(scene, tracer, particles, settings, context, statistics);
}

}  // namespace bakegi::meshless
