// What the antiradiance solver precomputes from geometry, materials and the "shapes" settings
// alone: bins, spreading tables, element hierarchy and links (§3.3, relighting without
// relinking). Relighting reuses it in memory, and the precomputation cache
// (precomputation_cache.h) saves and reloads it across sessions.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/global_pass.h"
#include "solvers/antiradiance/link_refinement.h"
#include "solvers/solver.h"

namespace bakegi {

struct AntiradiancePrecomputation : Precomputation {
  AntiradiancePrecomputation(antiradiance::DirectionalBins bins_in,
                             antiradiance::BinSpreading spreading_in)
      : bins(std::move(bins_in)), spreading(std::move(spreading_in)) {}

  antiradiance::DirectionalBins bins;
  antiradiance::BinSpreading spreading;
  antiradiance::ElementHierarchy hierarchy;
  antiradiance::GlobalPass transport;
  antiradiance::LinkingStatistics link_statistics;
  // Kept so that a bake that loads it from the cache reports what the bake that made it did.
  std::vector<std::string> warnings;
  double seconds = 0.0;  // precompute() from start to end

  size_t memory_bytes() const override {
    return spreading.memory_bytes() + hierarchy.memory_bytes() + transport.memory_bytes();
  }
};

}  // namespace bakegi
