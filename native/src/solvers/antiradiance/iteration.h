// §2.2: solving L = E + K U (L − A), A = J U (L − A) by iteration, in the progressive form
// the passes implement: the tables hold the newest bounce only (I_ex), each iteration
// propagates it (global pass U, push), reflects and re-emits it (local pass K, J) and adds
// its incident irradiance to E_acc; E_acc converges to the indirect irradiance.
//
//  - Symmetric (the paper's default): one U, one K and J per iteration.
//  - Asymmetric (provably convergent): per bounce, antiradiance steps with the bounce's
//    radiance frozen (A ← J U (L − A), repeated `antiradiance_steps` times or until A stops
//    changing), then one radiance step; the J-only and K-only updates act on the back and the
//    front hemisphere of each patch respectively.
//
// The residual of an iteration is the flux it added to E_acc relative to the total so far.
// The symmetric scheme is not proven to converge: when the added flux grows for
// `growth_patience` iterations in a row, the total exceeds `flux_bound`, or anything turns
// non-finite, the driver solves again with the asymmetric scheme from the direct seed and
// records a warning. The asymmetric scheme converges for the continuous operators, but the
// discretized U can create energy (few bins, coarse patches near each other): when it fails
// the same way, the driver restores the last good state, stops and warns.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/directional_bins.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "solvers/antiradiance/global_pass.h"
#include "solvers/antiradiance/radiance_tables.h"

namespace bakegi {
class JobContext;
}

namespace bakegi::antiradiance {

enum class IterationScheme { kSymmetric, kAsymmetric };

struct IterationOptions {
  IterationScheme scheme = IterationScheme::kSymmetric;
  int max_iterations = 32;     // radiance bounces (both schemes)
  double tolerance = 1e-4;     // stop when the residual falls below it
  int antiradiance_steps = 4;  // asymmetric: J steps per bounce at most
  int growth_patience = 3;     // growing iterations before the fallback (or the stop)
  // Σ_patches a · luminance(E_acc) that no solution can exceed (see flux_bound() in the
  // solver); beyond it the iteration counts as diverged.
  double flux_bound = std::numeric_limits<double>::infinity();
};

struct IterationRecord {
  int iteration = 0;      // 1-based bounce number
  double added_flux = 0;  // Σ_patches a · luminance(E) added to E_acc by this iteration
  double residual = 0;    // added_flux / total flux in E_acc after it
  double seconds = 0;
};

struct IterationResult {
  std::vector<IterationRecord> history;
  IterationScheme scheme_used = IterationScheme::kSymmetric;
  bool converged = false;
  bool fell_back = false;  // the symmetric scheme grew; the asymmetric one solved from the start
  bool stopped_early = false;  // the asymmetric scheme grew too: the last good state is kept
  std::string warning;         // empty unless fell_back or not converged
};

// Precondition: tables initialised by initialize_direct (I_ex seeded and pulled, E_acc 0).
// Honours cancel and reports progress through the context when given.
IterationResult iterate(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                        const BinSpreading& spreading, const GlobalPass& transport,
                        RadianceTables& tables, const IterationOptions& options,
                        JobContext* context = nullptr);

}  // namespace bakegi::antiradiance
