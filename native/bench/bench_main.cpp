// bakegi_bench: Embree's raw ray rate and the path tracer's ray rate on one scene
// (BAKEGI_BENCH_SCENE=file.bgs, else the procedural Cornell box). See docs/benchmarks.md.
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
