// Hierarchical Poisson-disk placement of the meshless basis points (Lehtinen et al. 2008,
// §2.3): dart throwing over importance-particle candidates (importance_particles.h) under
// the 5D distance D of Eq. 11, starting at spacing R_coarse and halving it per level, each
// level independent of the others; a level ends after `max_failures` rejections in a row.
// Coarse points are kept out of tight places by the harmonic mean distance test.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/bake_points.h"
#include "solvers/meshless/importance_particles.h"
#include "solvers/meshless/weight_function.h"

namespace bakegi {
struct Scene;
class RayTracer;
class JobContext;
}  // namespace bakegi

namespace bakegi::meshless {

struct PlacementSettings {
  // R_coarse, the Poisson-disk spacing of level 0 (m); 0 = automatic (see
  // automatic_coarse_spacing).
  float coarse_spacing = 0.0f;
  // Number of levels L + 1; 0 = automatic (see automatic_level_count).
  uint32_t levels = 0;
  // A level is full after this many rejected candidates in a row (the paper's 2000).
  uint32_t max_failures = 2000;
  // Support radius r = C R, C linear in the level from c_coarse (level 0) to c_fine (level L).
  float c_coarse = 1.5f;
  float c_fine = 2.5f;
  // Reject candidates whose harmonic mean distance to the geometry over the hemisphere
  // (rays of length 3R) is below R / 6 (§2.3, last paragraph).
  bool harmonic_mean_rejection = true;
  // Rays per harmonic mean test, stratified over the hemisphere (rounded to a square). With
  // 64 (8 x 8 jittered) the estimate's relative noise is ~4.5% at its worst (a point R/20
  // from a perpendicular wall, H = 1.16 R/6), so decisions flip only within ~10% of the
  // threshold; 16 rays give ~20% (17% of such points wrongly rejected), 256 give ~1% at 4x
  // the rays. Measured by simulating the estimator on that geometry (2000 trials each).
  uint32_t harmonic_rays = 64;
  uint64_t seed = 0;
  // Largest total number of points: placement refuses (levels given) or drops fine levels
  // (levels automatic) when the estimate exceeds it, and stops with an error if the real
  // count does.
  uint64_t max_points = 2'000'000;
  ParticleSettings particles;  // its seed is derived from `seed` per level
};

struct LevelStatistics {
  float spacing = 0.0f;         // R of the level
  float support_radius = 0.0f;  // r = C R
  uint64_t estimated_points = 0;
  uint64_t points = 0;
  uint64_t candidates = 0;           // candidates thrown
  uint64_t harmonic_rejections = 0;  // candidates that passed the Poisson test but not this
};

struct PlacementStatistics {
  float reachable_area = 0.0f;    // m², triangles the pilot particles reached
  float reachable_extent = 0.0f;  // m, diagonal of the pilot candidates' bounding box
  float mean_free_path = 0.0f;    // m, mean distance from a pilot candidate to the next surface
  bool levels_reduced = false;    // automatic levels lowered to fit max_points
  uint64_t particle_rays = 0;
  uint64_t harmonic_mean_rays = 0;
  std::vector<LevelStatistics> levels;
};

// R_coarse when the settings leave it at 0, from the scene's mean free path l (the mean
// distance a cosine-distributed ray from a reachable surface travels to the next one; 4V/S
// in a closed convex room) and its reachable area A:
//   R_coarse = 0.36 l (n / 17.8)^(1/6),  n = A / l^2.
// Indirect light varies over about the distance to the surfaces it comes from, so the
// coarsest level follows l; n counts the scene's "room faces" (17.8 in the Cornell box, 535
// in Sponza), and the sixth root lets a large scene's coarse count grow as n^(2/3) rather
// than n: the same trade as the rule this replaced (R = 0.1475 m^(1/3) A^(1/3), coarse count
// ~ A^(1/3)), which assumed metres and was 22-26% off at 1 mm and 1 km
// (python_tests/test_scale.py). Neither l nor n has a unit, so neither has the rule. The
// factor keeps the spacing study's Cornell box value (l = 1.17 m, R = 0.43 m: 6.3% in 3 s,
// where R = 0.86 m gave 10.8%; docs/methods/meshless.md). Without the sixth root (R = 0.36 l)
// Sponza took 3x as long (570 s, 388k points) for an error still over 100%.
float automatic_coarse_spacing(float mean_free_path, float reachable_area);
// Levels when the settings leave them at 0: four (the spacing study: at equal point counts a
// finer coarsest level with four levels beats five or six levels), fewer when the finest
// spacing would fall below l / 60 (2 cm in the Cornell box: indirect light varies little
// over less).
uint32_t automatic_level_count(float coarse_spacing, float mean_free_path);
// Expected Poisson-disk points on a flat area: random sequential adsorption of disks of
// diameter R jams at 54.7% coverage, so N = 0.547 A / (pi R^2 / 4) = 0.70 A / R^2.
double estimated_point_count(double area, double spacing);

// Places the points with particles starting at `viewpoint`. Points come out level by level
// (level 0 first), each with radius C R_level. Throws Error(INVALID_ARGUMENT) for bad
// settings, when the point count would exceed max_points and when a level gets no point at
// all (the harmonic mean test rejected everything), Error(CANCELLED) on cancel.
std::vector<BasisPoint> place_points(const Scene& scene, const RayTracer& tracer,
                                     const glm::vec3& viewpoint, const PlacementSettings& settings,
                                     JobContext& context,
                                     PlacementStatistics* statistics = nullptr);
// The same with particles leaving `surfaces` (e.g. the bake points) on their front side.
std::vector<BasisPoint> place_points(const Scene& scene, const RayTracer& tracer,
                                     const BakePoints& surfaces, const PlacementSettings& settings,
                                     JobContext& context,
                                     PlacementStatistics* statistics = nullptr);

}  // namespace bakegi::meshless
