// The meshless basis (solvers/meshless/basis_hierarchy.h, multilevel_approximation.h) on
// ~100k hand-made points over 6 levels: jittered grids on the 6 inner faces of a unit cube
// (a room: walls, corners and edges where supports cross surfaces), spacing halving per
// level, r = C R with C from 1.5 to 2.5 (§2.3). Benchmarks: hierarchy build (R-trees + DAG)
// with 1 thread and all threads, P and P† on RGB values, evaluate-many of 100k bake points
// on the hierarchy and on its flattened single level.
//
// Measured (16-core device machine, idle, medians of 3): build 659 ms on 1 thread, 128 ms on
// 16 (so the DAG build runs in parallel); 64.7 MB, 46 coarser_basis and 17.8 neighbor entries
// per point. Evaluate-many 100k RGB: 995 ms on 1 thread (~10 us per query over 6 levels,
// mostly R-tree traversal), 87 ms on 16; flattened: 24.5 ms on 16. P 1.7 ms, P† 3.8 ms.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include <tbb/global_control.h>

#include "solvers/meshless/basis_hierarchy.h"
#include "solvers/meshless/multilevel_approximation.h"
#include "util/random.h"

namespace bakegi::bench {
namespace {

using namespace meshless;

constexpr uint32_t kLevels = 6;
// Finest spacing 1/112 on 6 unit faces: 6 * 112^2 = 75k finest points, ~100k in all.
constexpr int kFinestCells = 112;

glm::vec3 face_point(int face, float u, float v) {
  const int axis = face / 2;
  const float side = float(face % 2);
  glm::vec3 x;
  x[axis] = side;
  x[(axis + 1) % 3] = u;
  x[(axis + 2) % 3] = v;
  return x;
}

glm::vec3 face_normal(int face) {
  glm::vec3 n(0.0f);
  n[face / 2] = face % 2 ? -1.0f : 1.0f;  // inward: the room's visible sides
  return n;
}

std::vector<BasisPoint> room_points() {
  Pcg32 rng(17, 3);
  std::vector<BasisPoint> points;
  for (uint32_t l = 0; l < kLevels; ++l) {
    const int cells = kFinestCells >> (kLevels - 1 - l);
    const float h = 1.0f / float(cells);
    for (int face = 0; face < 6; ++face)
      for (int i = 0; i < cells; ++i)
        for (int k = 0; k < cells; ++k) {
          BasisPoint p;
          p.position = face_point(face, (float(i) + 0.25f + 0.5f * rng.next_float()) * h,
                                  (float(k) + 0.25f + 0.5f * rng.next_float()) * h);
          p.normal = face_normal(face);
          p.radius = (1.5f + float(l) / float(kLevels - 1)) * h;
          p.level = l;
          points.push_back(p);
        }
  }
  return points;
}

float irradiance(const glm::vec3& x, int channel) {
  return 1.0f + 0.5f * std::sin(6.0f * x.x + float(channel)) * std::cos(5.0f * x.y) + 0.2f * x.z;
}

struct Fixture {
  std::vector<BasisPoint> points = room_points();
  BasisHierarchy basis{points};
  std::vector<float> samples;
  std::vector<glm::vec3> query_positions, query_normals;

  Fixture() {
    samples.resize(basis.size() * 3);
    for (uint32_t j = 0; j < basis.size(); ++j)
      for (int c = 0; c < 3; ++c) samples[j * 3 + c] = irradiance(basis.point(j).position, c);
    Pcg32 rng(23, 5);
    for (int q = 0; q < 100000; ++q) {
      const int face = int(rng.next_uint() % 6);
      query_positions.push_back(face_point(face, rng.next_float(), rng.next_float()));
      query_normals.push_back(face_normal(face));
    }
  }
};

const Fixture& fixture() {
  static const Fixture instance;
  return instance;
}

void report_shape(benchmark::State& state, const BasisHierarchy& basis) {
  size_t coarser = 0, neighbors = 0;
  for (uint32_t j = 0; j < basis.size(); ++j) {
    coarser += basis.coarser_basis(j).size();
    neighbors += basis.neighbors(j).size();
  }
  state.counters["points"] = double(basis.size());
  state.counters["levels"] = double(basis.level_count());
  state.counters["memory_MB"] = double(basis.memory_bytes()) / (1 << 20);
  state.counters["coarser_per_point"] = double(coarser) / double(basis.size());
  state.counters["neighbors_per_point"] = double(neighbors) / double(basis.size());
}

// Arg: TBB threads (0 = all).
void BM_MeshlessBasisBuild(benchmark::State& state) {
  const std::vector<BasisPoint>& points = fixture().points;
  std::unique_ptr<tbb::global_control> limit;
  if (state.range(0) > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(state.range(0)));
  for (auto _ : state) {
    BasisHierarchy basis(points);
    benchmark::DoNotOptimize(basis.size());
  }
  report_shape(state, fixture().basis);
}
BENCHMARK(BM_MeshlessBasisBuild)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

void BM_MeshlessProjectRgb(benchmark::State& state) {
  const Fixture& f = fixture();
  for (auto _ : state) benchmark::DoNotOptimize(project_samples(f.basis, f.samples, 3).data());
}
BENCHMARK(BM_MeshlessProjectRgb)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

void BM_MeshlessPullPushRgb(benchmark::State& state) {
  const Fixture& f = fixture();
  for (auto _ : state) benchmark::DoNotOptimize(pull_push_project(f.basis, f.samples, 3).data());
}
BENCHMARK(BM_MeshlessPullPushRgb)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

// Arg: TBB threads (0 = all).
void BM_MeshlessEvaluateManyRgb(benchmark::State& state) {
  const Fixture& f = fixture();
  const std::vector<float> alpha = project_samples(f.basis, f.samples, 3);
  std::vector<float> out(f.query_positions.size() * 3);
  std::unique_ptr<tbb::global_control> limit;
  if (state.range(0) > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(state.range(0)));
  for (auto _ : state)
    benchmark::DoNotOptimize(
        evaluate_many(f.basis, alpha, 3, f.query_positions, f.query_normals, out));
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(f.query_positions.size()));
}
BENCHMARK(BM_MeshlessEvaluateManyRgb)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

void BM_MeshlessFlatEvaluateManyRgb(benchmark::State& state) {
  const Fixture& f = fixture();
  const std::vector<float> alpha = project_samples(f.basis, f.samples, 3);
  const FlatExpansion flat = flatten(f.basis, alpha, 3);
  std::vector<float> out(f.query_positions.size() * 3);
  for (auto _ : state)
    benchmark::DoNotOptimize(
        evaluate_many(flat.basis, flat.coefficients, 3, f.query_positions, f.query_normals, out));
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(f.query_positions.size()));
}
BENCHMARK(BM_MeshlessFlatEvaluateManyRgb)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

void BM_MeshlessFlatten(benchmark::State& state) {
  const Fixture& f = fixture();
  const std::vector<float> alpha = project_samples(f.basis, f.samples, 3);
  for (auto _ : state) benchmark::DoNotOptimize(flatten(f.basis, alpha, 3).coefficients.data());
}
BENCHMARK(BM_MeshlessFlatten)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

}  // namespace
}  // namespace bakegi::bench
