// The limit: how many closest-hit rays per second Embree traces on the benchmark scene for
// incoherent, diffuse-bounce-like rays, each way at 1 and 2 threads:
//  - BM_EmbreeSingleRays: RayTracer::intersect (rtcIntersect1) per ray, as the path tracer;
//  - BM_EmbreePackets16: RayTracer::intersect_many, 16-wide packets;
//  - BM_EmbreeShadowRays: RayTracer::occluded between random surface points (the path
//    tracer's other kind of ray, next-event estimation's shadow rays).
// Threads are TBB workers limited by tbb::global_control; rays/s is the counter to read.
#include <algorithm>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "bench_scene.h"
#include "diffuse_rays.h"

namespace bakegi::bench {
namespace {

// 1M rays: large enough that a pass lasts ~0.1 s and the rays do not fit in cache.
constexpr size_t kRayCount = size_t(1) << 20;

const std::vector<Ray>& rays() {
  static const std::vector<Ray> r = diffuse_bounce_rays(bench_scene().scene, kRayCount);
  return r;
}

const std::vector<Ray>& segments() {
  static const std::vector<Ray> r = surface_to_surface_segments(bench_scene().scene, kRayCount);
  return r;
}

// hits: rays that hit something (closest hit) or were occluded (shadow rays).
void report(benchmark::State& state, size_t hits) {
  state.counters["rays/s"] =
      benchmark::Counter(double(state.iterations()) * kRayCount, benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / double(kRayCount);
  state.counters["triangles"] = double(bench_scene().scene.triangles.size());
  state.SetLabel(bench_scene().name);
}

void BM_EmbreeSingleRays(benchmark::State& state) {
  const int threads = int(state.range(0));
  const RayTracer& tracer = *bench_scene().tracer;
  const std::vector<Ray>& r = rays();
  std::vector<Hit> hits(r.size());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  for (auto _ : state) {
    for_each_ray(r.size(), [&](size_t i) { hits[i] = tracer.intersect(r[i]); });
    benchmark::DoNotOptimize(hits.data());
  }
  report(state,
         size_t(std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.hit; })));
}

void BM_EmbreePackets16(benchmark::State& state) {
  const int threads = int(state.range(0));
  const RayTracer& tracer = *bench_scene().tracer;
  const std::vector<Ray>& r = rays();
  std::vector<Hit> hits(r.size());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  for (auto _ : state) {
    tracer.intersect_many(r.data(), hits.data(), r.size());
    benchmark::DoNotOptimize(hits.data());
  }
  report(state,
         size_t(std::count_if(hits.begin(), hits.end(), [](const Hit& h) { return h.hit; })));
}

void BM_EmbreeShadowRays(benchmark::State& state) {
  const int threads = int(state.range(0));
  const RayTracer& tracer = *bench_scene().tracer;
  const std::vector<Ray>& r = segments();
  std::vector<uint8_t> occluded(r.size());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  for (auto _ : state) {
    for_each_ray(r.size(), [&](size_t i) { occluded[i] = tracer.occluded(r[i]) ? 1 : 0; });
    benchmark::DoNotOptimize(occluded.data());
  }
  report(state, size_t(std::count(occluded.begin(), occluded.end(), uint8_t{1})));
}

BENCHMARK(BM_EmbreeSingleRays)->Apply(at_one_and_two_threads);
BENCHMARK(BM_EmbreePackets16)->Apply(at_one_and_two_threads);
BENCHMARK(BM_EmbreeShadowRays)->Apply(at_one_and_two_threads);

}  // namespace
}  // namespace bakegi::bench
