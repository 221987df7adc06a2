// What a path pays for its random numbers before tracing: making one sample's stream and
// drawing the numbers of a short path (the 6 quasi-random ones and 6 more), for the plain
// PCG stream and the path tracer's Sobol' stream (util/random.h). The time per iteration is
// the cost of one stream; for scale, a path in the exported Cornell box (scenes/) traces
// about 6 rays in ~4 microseconds of one core.
#include <benchmark/benchmark.h>

#include "util/random.h"

namespace bakegi::bench {
namespace {

template <RandomStream (*Make)(uint64_t, uint64_t, uint64_t)>
void BM_SampleStream(benchmark::State& state) {
  uint64_t sample = 0;
  float sum = 0.0f;
  for (auto _ : state) {
    RandomStream stream = Make(7, 12345, sample++);
    for (int k = 0; k < 12; ++k) sum += stream.next_float();
  }
  benchmark::DoNotOptimize(sum);
}

BENCHMARK_TEMPLATE(BM_SampleStream, sample_stream)->Name("BM_PcgSampleStream");
BENCHMARK_TEMPLATE(BM_SampleStream, sobol_sample_stream)->Name("BM_SobolSampleStream");

}  // namespace
}  // namespace bakegi::bench
