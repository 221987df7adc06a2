// Meshless point placement (Lehtinen et al. 2008, §2.3) on the benchmark scene
// (BAKEGI_BENCH_SCENE=file.bgs, else the procedural Cornell box) with the automatic
// R_coarse and level count: from a viewpoint at the centre of the scene's bounding box, and
// from the scene's bake points. Counters: points per level (L0, L1, ...), total points,
// rays traced, and R_coarse (mm) and reachable area (m²) as the pilot found them.
//
// Settings from the environment (see also dump below): BAKEGI_BENCH_MESHLESS_R (R_coarse in m, 0 =
// automatic), BAKEGI_BENCH_MESHLESS_LEVELS (0 = automatic), BAKEGI_BENCH_MESHLESS_HARMONIC (0 =
// off).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_scene.h"
#include "solvers/meshless/point_placement.h"
#include "util/job_context.h"

namespace bakegi::bench {
namespace {

double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text && *text ? std::strtod(text, nullptr) : fallback;
}

meshless::PlacementSettings settings_from_environment() {
  meshless::PlacementSettings settings;
  settings.coarse_spacing = float(env_number("BAKEGI_BENCH_MESHLESS_R", 0.0));
  settings.levels = uint32_t(env_number("BAKEGI_BENCH_MESHLESS_LEVELS", 0.0));
  settings.harmonic_mean_rejection = env_number("BAKEGI_BENCH_MESHLESS_HARMONIC", 1.0) != 0.0;
  return settings;
}

// BAKEGI_BENCH_MESHLESS_DUMP=prefix writes the points to prefix_<mode>.txt, one per line:
// position, normal, radius, level (for plots).
void dump(const std::vector<meshless::BasisPoint>& points, const char* mode) {
  const char* prefix = std::getenv("BAKEGI_BENCH_MESHLESS_DUMP");
  if (!prefix || !*prefix) return;
  const std::string path = std::string(prefix) + "_" + mode + ".txt";
  FILE* file = std::fopen(path.c_str(), "w");
  if (!file) return;
  for (const auto& p : points) {
    std::fprintf(file, "%.7g %.7g %.7g %.7g %.7g %.7g %.7g %u\n", p.position.x, p.position.y,
                 p.position.z, p.normal.x, p.normal.y, p.normal.z, p.radius, p.level);
  }
  std::fclose(file);
}

void report(benchmark::State& state, const meshless::PlacementStatistics& statistics,
            size_t points) {
  for (size_t l = 0; l < statistics.levels.size(); ++l) {
    state.counters["L" + std::to_string(l)] = double(statistics.levels[l].points);
  }
  state.counters["points"] = double(points);
  state.counters["R_coarse_mm"] =
      statistics.levels.empty() ? 0.0 : 1000.0 * statistics.levels[0].spacing;
  state.counters["area_m2"] = statistics.reachable_area;
  state.counters["particle_rays"] = double(statistics.particle_rays);
  state.counters["harmonic_rays"] = double(statistics.harmonic_mean_rays);
}

void BM_MeshlessPlacementFromViewpoint(benchmark::State& state) {
  const BenchScene& bench = bench_scene();
  const glm::vec3 viewpoint = 0.5f * (bench.scene.bounds_min + bench.scene.bounds_max);
  const meshless::PlacementSettings settings = settings_from_environment();
  for (auto _ : state) {
    JobContext context;
    meshless::PlacementStatistics statistics;
    const auto points = meshless::place_points(bench.scene, *bench.tracer, viewpoint, settings,
                                               context, &statistics);
    dump(points, "viewpoint");
    report(state, statistics, points.size());
  }
}
BENCHMARK(BM_MeshlessPlacementFromViewpoint)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_MeshlessPlacementFromBakePoints(benchmark::State& state) {
  const BenchScene& bench = bench_scene();
  const meshless::PlacementSettings settings = settings_from_environment();
  for (auto _ : state) {
    JobContext context;
    meshless::PlacementStatistics statistics;
    const auto points = meshless::place_points(bench.scene, *bench.tracer, bench.points, settings,
                                               context, &statistics);
    dump(points, "bake_points");
    report(state, statistics, points.size());
  }
}
BENCHMARK(BM_MeshlessPlacementFromBakePoints)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace bakegi::bench
