// Antiradiance stages on the benchmark scene (BAKEGI_BENCH_SCENE=file.bgs, else the procedural
// Cornell box): linking, the global pass alone, and whole symmetric iterations (global pass,
// push, local pass, pull) split into their stages. The office target is 4 iterations
// in ≤ 50 ms and linking in ≤ 5 s at about 20k elements and 600k links.
//
// Settings from the environment (the solver's defaults when unset):
//   BAKEGI_BENCH_BINS=192            directional bins
//   BAKEGI_BENCH_PATCH_SIZE=0.5      patch size in metres (0: default_max_edge)
//   BAKEGI_BENCH_ORACLE_FACTOR=1     LinkingOptions::oracle_factor
//   BAKEGI_BENCH_ORACLE=sender|both  LinkingOptions::test_receiver (both: true)
//   BAKEGI_BENCH_EXTENT=sphere|projected  LinkingOptions::extent
//
// Besides wall time per iteration, every benchmark reports cpu_ms (the CPU time of all
// threads, Google Benchmark's process CPU time): on a shared machine the wall time varies with
// the other load, the CPU time much less; cpu_ms / threads bounds the uncontended wall time.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_scene.h"
#include "lights/direct_light.h"
#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/direct_initialization.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/global_pass.h"
#include "solvers/antiradiance/iteration.h"
#include "solvers/antiradiance/link_refinement.h"
#include "solvers/antiradiance/local_pass.h"
#include "solvers/antiradiance/push_pull.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/job_context.h"

namespace bakegi::bench {
namespace {

using namespace antiradiance;
using Clock = std::chrono::steady_clock;

double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text && *text ? std::strtod(text, nullptr) : fallback;
}

std::string env_text(const char* name, const char* fallback) {
  const char* text = std::getenv(name);
  return text && *text ? text : fallback;
}

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

LinkingOptions linking_options() {
  LinkingOptions options;
  options.oracle_factor = env_number("BAKEGI_BENCH_ORACLE_FACTOR", options.oracle_factor);
  const std::string oracle = env_text("BAKEGI_BENCH_ORACLE", "");
  if (oracle == "sender") options.test_receiver = false;
  if (oracle == "both") options.test_receiver = true;
  const std::string extent = env_text("BAKEGI_BENCH_EXTENT", "");
  if (extent == "sphere") options.extent = OracleExtent::kBoundingSphere;
  if (extent == "projected") options.extent = OracleExtent::kProjectedArea;
  return options;
}

// Everything the passes need, built once: hierarchy, bins, links, tables seeded with direct
// light (16 samples per patch: the values only need to be realistic, not converged).
struct Stages {
  const BenchScene& bench = bench_scene();
  DirectionalBins bins =
      DirectionalBins::from_bin_count(int64_t(env_number("BAKEGI_BENCH_BINS", 192)));
  BinSpreading spreading{bins};
  ElementHierarchy hierarchy;
  LinkingStatistics linking;
  GlobalPass transport;
  std::vector<glm::vec3> direct;

  Stages() {
    const double patch_size = env_number("BAKEGI_BENCH_PATCH_SIZE", 0.0);
    hierarchy = ElementHierarchy(bench.scene, HierarchyOptions{float(patch_size), 0});
    LinkSet set = build_links(hierarchy, bins, spreading, linking_options());
    linking = set.statistics;
    transport = GlobalPass(std::move(set.links), hierarchy.element_count(), spreading);
    const DirectLight light(bench.scene, *bench.tracer);
    JobContext context;
    direct = direct_irradiance_at_patches(hierarchy, light, 16, 0, context);
  }

  std::unique_ptr<RadianceTables> seeded_tables() const {
    auto tables = std::make_unique<RadianceTables>(hierarchy.element_count(),
                                                   hierarchy.patch_count(), bins.bin_count());
    initialize_direct(hierarchy, bins, direct, *tables);
    return tables;
  }

  void describe(benchmark::State& state) const {
    state.counters["elements"] = double(hierarchy.element_count());
    state.counters["links"] = double(linking.link_count);
    state.counters["bins"] = double(bins.bin_count());
    state.counters["link_MB"] = double(transport.memory_bytes()) / double(1 << 20);
    state.counters["table_MB"] =
        double(RadianceTables::bytes(hierarchy.element_count(), hierarchy.patch_count(),
                                     uint64_t(bins.bin_count()))) /
        double(1 << 20);
    // Spread links (class > 0) and filter taps (bin updates) per global pass: the pass's
    // work is about one tap per unspread link plus the filter length of each spread one.
    uint64_t spread = 0, taps = 0;
    for (const Link& link : transport.links()) {
      spread += link.spread_class != 0;
      taps += spreading.filter(link.spread_class, link.bin).bins.size();
    }
    state.counters["spread_links"] = double(spread);
    state.counters["taps"] = double(taps);
    state.SetLabel(bench.name);
  }
};

const Stages& stages() {
  static const Stages built;
  return built;
}

void BM_AntiradianceLinking(benchmark::State& state) {
  const Stages& s = stages();
  const LinkingOptions options = linking_options();
  uint64_t links = 0;
  for (auto _ : state) {
    LinkSet set = build_links(s.hierarchy, s.bins, s.spreading, options);
    links = set.statistics.link_count;
    benchmark::DoNotOptimize(set.links.data());
  }
  s.describe(state);
  state.counters["links"] = double(links);
}

// Grouping the links by receiver (the GlobalPass constructor), which the solver reports as
// part of its "tables" stage.
void BM_AntiradianceLinkGrouping(benchmark::State& state) {
  const Stages& s = stages();
  const LinkingOptions options = linking_options();
  for (auto _ : state) {
    state.PauseTiming();
    LinkSet set = build_links(s.hierarchy, s.bins, s.spreading, options);
    state.ResumeTiming();
    GlobalPass pass(std::move(set.links), s.hierarchy.element_count(), s.spreading);
    benchmark::DoNotOptimize(pass.links().data());
  }
  s.describe(state);
}

void BM_AntiradianceGlobalPass(benchmark::State& state) {
  const Stages& s = stages();
  const auto tables = s.seeded_tables();
  // One iteration first, so that the back bins hold antiradiance as they do later on.
  s.transport.run(s.spreading, *tables);
  push(s.hierarchy, *tables);
  local_pass(s.hierarchy, s.bins, *tables);
  pull(s.hierarchy, *tables);
  for (auto _ : state) s.transport.run(s.spreading, *tables);
  s.describe(state);
}

// `iterations` symmetric iterations from the direct seed, as iterate() runs them (residuals,
// snapshots), with the time of each stage measured separately on the side.
void BM_AntiradianceIterations(benchmark::State& state) {
  const Stages& s = stages();
  const int iterations = int(state.range(0));
  IterationOptions options;
  options.max_iterations = iterations;
  options.tolerance = 0.0;
  double stage_ms[4] = {0, 0, 0, 0};
  double recorded_ms = 0.0;  // the iterations' own timing (IterationRecord::seconds)
  uint64_t runs = 0, fell_back = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const auto tables = s.seeded_tables();
    state.ResumeTiming();
    const IterationResult result =
        iterate(s.hierarchy, s.bins, s.spreading, s.transport, *tables, options);
    benchmark::DoNotOptimize(result.history.size());
    state.PauseTiming();
    for (const IterationRecord& record : result.history) recorded_ms += 1e3 * record.seconds;
    fell_back += result.fell_back ? 1 : 0;
    // The stages alone, on fresh tables: global pass, push, local pass, pull.
    const auto staged = s.seeded_tables();
    for (int i = 0; i < iterations; ++i) {
      auto t = Clock::now();
      s.transport.run(s.spreading, *staged);
      stage_ms[0] += ms_since(t);
      t = Clock::now();
      push(s.hierarchy, *staged);
      stage_ms[1] += ms_since(t);
      t = Clock::now();
      local_pass(s.hierarchy, s.bins, *staged);
      stage_ms[2] += ms_since(t);
      t = Clock::now();
      pull(s.hierarchy, *staged);
      stage_ms[3] += ms_since(t);
    }
    ++runs;
    state.ResumeTiming();
  }
  s.describe(state);
  const double per = runs ? 1.0 / double(runs) : 0.0;
  state.counters["global_ms"] = stage_ms[0] * per;
  state.counters["push_ms"] = stage_ms[1] * per;
  state.counters["local_ms"] = stage_ms[2] * per;
  state.counters["pull_ms"] = stage_ms[3] * per;
  state.counters["iterate_ms"] = recorded_ms * per;
  // Runs in which the symmetric scheme grew and iterate() went on with the asymmetric one.
  state.counters["fell_back"] = double(fell_back) * per;
}

BENCHMARK(BM_AntiradianceLinking)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK(BM_AntiradianceLinkGrouping)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK(BM_AntiradianceGlobalPass)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_AntiradianceIterations)
    ->Arg(1)
    ->Arg(4)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace bakegi::bench
