// Embree alone on the path tracer's own rays: the limit the path tracer's ray rate is
// measured against (BM_PathtraceJob's rays/s_tracing).
//
// The rays of diffuse_rays.h are cheaper than the path tracer's: they leave from points
// uniform over the surface area (the path tracer's first rays leave from bake points, many
// in dense geometry), and their shadow segments join two random surface points, mostly
// occluded, so Embree stops at the first blocker (the path tracer's shadow rays run to the
// lights and mostly arrive, traversing to the end). On Sponza the path tracer's rays cost
// Embree about twice as much as those. Here the rays are recorded while sample_indirect
// traces 4 paths at every bake point (one thread, RayTracer::record_rays), then replayed in
// the order traced through intersect() and occluded(), at 1 and 2 threads.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <vector>

#include "bench_scene.h"
#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "util/random.h"

namespace bakegi::bench {
namespace {

constexpr int kPathsPerPoint = 4;
constexpr int kMaxBounces = 64;  // the path tracer's default

const std::vector<RecordedRay>& path_rays() {
  static const std::vector<RecordedRay> recorded = [] {
    const BenchScene& bench = bench_scene();
    std::vector<RecordedRay> log;
    log.reserve(bench.points.size() * kPathsPerPoint * 6);
    const DirectLight direct(bench.scene, *bench.tracer);
    bench.tracer->record_rays(&log);
    uint64_t rays = 0;
    for (size_t i = 0; i < bench.points.size(); ++i) {
      const SurfacePoint x{bench.points.positions[i], bench.points.normals[i],
                           bench.points.normals[i]};
      RandomStream rng(1, i);
      for (int s = 0; s < kPathsPerPoint; ++s) sample_indirect(direct, x, rng, kMaxBounces, rays);
    }
    bench.tracer->record_rays(nullptr);
    return log;
  }();
  return recorded;
}

void BM_EmbreePathTracerRays(benchmark::State& state) {
  const int threads = int(state.range(0));
  const RayTracer& tracer = *bench_scene().tracer;
  const std::vector<RecordedRay>& r = path_rays();
  std::vector<uint8_t> hit(r.size());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  for (auto _ : state) {
    for_each_ray(r.size(), [&](size_t i) {
      hit[i] = r[i].occlusion ? tracer.occluded(r[i].ray) : tracer.intersect(r[i].ray).hit;
    });
    benchmark::DoNotOptimize(hit.data());
  }
  size_t occlusion = 0;
  for (const RecordedRay& ray : r) occlusion += ray.occlusion ? 1 : 0;
  state.counters["rays/s"] = benchmark::Counter(double(state.iterations()) * double(r.size()),
                                                benchmark::Counter::kIsRate);
  state.counters["rays"] = double(r.size());
  state.counters["shadow_fraction"] = double(occlusion) / double(r.size());
  state.counters["rays_per_path"] =
      double(r.size()) / (double(bench_scene().points.size()) * kPathsPerPoint);
  state.SetLabel(bench_scene().name);
}

BENCHMARK(BM_EmbreePathTracerRays)->Apply(at_one_and_two_threads);

// The same rays split by kind (closest hits, then shadow rays, each in the order traced),
// one thread, one ray at a time (stream 0) or through Embree's stream interface `stream`
// rays a call: whether a path tracer that traces its rays in batches (a point's paths
// vertex by vertex, or wavefronts) would gain from the stream interface itself.
void BM_EmbreePathTracerRaysByKind(benchmark::State& state) {
  const size_t stream = size_t(state.range(0));
  const RayTracer& tracer = *bench_scene().tracer;
  std::vector<Ray> closest, shadow;
  for (const RecordedRay& r : path_rays()) (r.occlusion ? shadow : closest).push_back(r.ray);
  std::vector<Hit> hits(closest.size());
  std::vector<uint8_t> blocked(shadow.size());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  for (auto _ : state) {
    if (stream) {
      tracer.intersect_stream(closest.data(), hits.data(), closest.size(), stream);
      tracer.occluded_stream(shadow.data(), blocked.data(), shadow.size(), stream);
    } else {
      for (size_t i = 0; i < closest.size(); ++i) hits[i] = tracer.intersect(closest[i]);
      for (size_t i = 0; i < shadow.size(); ++i) blocked[i] = tracer.occluded(shadow[i]);
    }
    benchmark::DoNotOptimize(hits.data());
    benchmark::DoNotOptimize(blocked.data());
  }
  state.counters["rays/s"] =
      benchmark::Counter(double(state.iterations()) * double(closest.size() + shadow.size()),
                         benchmark::Counter::kIsRate);
  state.SetLabel(bench_scene().name);
}

BENCHMARK(BM_EmbreePathTracerRaysByKind)->ArgName("stream")->Arg(0)->Arg(16)->Arg(256);

}  // namespace
}  // namespace bakegi::bench
