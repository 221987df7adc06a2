// The scene every benchmark of bakegi_bench uses: the .bgs file named by the environment
// variable BAKEGI_BENCH_SCENE (e.g. the exported Cornell box, with its bake points), or
// else the procedural Cornell box, so that the benchmarks always run. Loaded once.
#pragma once

#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "scene/bake_points.h"
#include "bakegi/bakegi.h"
#include "scene/ray_tracer.h"
#include "scene/scene.h"

namespace bakegi::bench {

struct BenchScene {
  std::string name;   // file path or "procedural Cornell box"
  Scene scene;        // validated and flattened
  BakePoints points;  // the file's, or one per triangle
  std::unique_ptr<RayTracer> tracer;
};

// Throws bakegi::Error if the file cannot be read or the scene is invalid.
const BenchScene& bench_scene();

// The same scene and points as C API handles, for benchmarks that run jobs.
struct CApiScene {
  bakegi_scene* scene = nullptr;
  bakegi_points* points = nullptr;
};
const CApiScene& bench_scene_c_api();

// body(i) for every i in [0, count) on the TBB workers (as many as a tbb::global_control
// allows), in blocks of 4096 rays.
template <typename Body>
void for_each_ray(size_t count, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 4096),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i != range.end(); ++i) body(i);
                    });
}

// A ray-rate benchmark's registration: at 1 and 2 threads (range(0)), wall time, in ms.
inline void at_one_and_two_threads(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
}

}  // namespace bakegi::bench
