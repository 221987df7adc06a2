#include "solvers/antiradiance/iteration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "solvers/antiradiance/local_pass.h"
#include "solvers/antiradiance/push_pull.h"
#include "util/error.h"
#include "util/job_context.h"
#include "util/luminance.h"

// The asymmetric scheme in the progressive form. The system is L = E + K U (L − A),
// A = J U (L − A): A is linear in L. Write the solution as a sum of bounces L = Σ_k d_k with
// d_0 = E (the direct seed) and A = Σ_k A_k, where A_k is the antiradiance OF d_k alone:
//
//   A_k = J U (d_k − A_k)          (a fixed point with d_k frozen)
//   G d_k := U (d_k − A_k)          (the incident radiance d_k produces, occlusion included)
//   d_{k+1} = K G d_k,   E_acc += E(G d_k).
//
// Summing over k gives back both equations, so the bounces add up to the solution. Per bounce,
// A_k is found by A ← J U (d_k − A) from A = 0 (the I_ex row holds d_k on the front bins and −A
// on the back ones, so each step is a global pass, a push and a J-only local pass); from 0 the
// iterates are the partial sums of the Neumann series Σ_n (−JU)^n JU d_k, i.e. exact for chains
// of up to n occluders after n steps, which is what `antiradiance_steps` truncates. The final
// L_in = U (d_k − A_k) then gives E and, through K, the next bounce.
//
// The next bounce starts from A = 0, not from −J L_in (the back bins the full local pass
// writes): J L_in = A_k is the antiradiance of d_k, not of d_{k+1}. Starting there is exactly
// the symmetric scheme's step (its antiradiance lags one bounce behind its radiance); a finite
// number of steps would then leave d_k's antiradiance applied to d_{k+1}, a bias that
// (JU)^n shrinks but never removes, while from 0 every truncated iterate is made of d_{k+1}
// alone. In a scene without occlusion A_k = J U d_k is reached in one step from 0.

namespace bakegi::antiradiance {

namespace {

using Clock = std::chrono::steady_clock;

// A bounce adding this many times the flux of the smallest bounce so far is divergence: a
// converging iteration adds less and less (the symmetric one wobbles by a few times at most
// when its late antiradiance arrives).
constexpr double kSurgeFactor = 10.0;

// Patch rows per task when snapshotting the tables.
constexpr size_t kSnapshotRowsPerTask = 256;

bool finite(glm::vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Σ_patches a · luminance(E).
double flux(const ElementHierarchy& hierarchy, std::span<const glm::vec3> irradiance) {
  const std::vector<Patch>& patches = hierarchy.patches();
  double sum = 0.0;
  for (size_t p = 0; p < patches.size(); ++p) {
    sum += double(hierarchy.elements()[patches[p].element].area) * luminance(irradiance[p]);
  }
  return sum;
}

// The solver's state between iterations: the patches' I_ex rows (clusters follow by pull) and
// the accumulated irradiance.
struct Snapshot {
  std::vector<glm::vec3> exitant;
  std::vector<glm::vec3> accumulated;
  size_t history_size = 0;
};

// `context` (optional) is checked for cancel every block of rows: at many bins a snapshot is
// over 100 MB (the Cornell box at 768 bins), and the iteration takes two before its first
// bounce, which once made up most of a cancel's 169 ms there.
void take(const ElementHierarchy& hierarchy, const RadianceTables& tables, size_t history_size,
          Snapshot& snapshot, const JobContext* context) {
  const size_t m = size_t(tables.bin_count());
  snapshot.exitant.resize(hierarchy.patch_count() * m);
  // Tens of MB per iteration: copied in parallel (each row by one task, so no ordering issue).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, hierarchy.patch_count(), kSnapshotRowsPerTask),
                    [&](const tbb::blocked_range<size_t>& block) {
                      if (context) context->throw_if_cancelled();
                      for (size_t p = block.begin(); p != block.end(); ++p) {
                        const auto row = tables.exitant(hierarchy.patches()[p].element);
                        std::copy(row.begin(), row.end(),
                                  snapshot.exitant.begin() + std::ptrdiff_t(p * m));
                      }
                    });
  const auto accumulated = tables.accumulated_irradiance();
  snapshot.accumulated.assign(accumulated.begin(), accumulated.end());
  snapshot.history_size = history_size;
}

// Restores the state and makes it safe to continue from: non-finite entries are zeroed (they
// may have been there from the start), clusters pulled.
void restore(const ElementHierarchy& hierarchy, const Snapshot& snapshot, RadianceTables& tables) {
  const size_t m = size_t(tables.bin_count());
  auto scrub = [](glm::vec3 v) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(v[c])) v[c] = 0.0f;
    }
    return v;
  };
  for (size_t p = 0; p < hierarchy.patch_count(); ++p) {
    const auto row = tables.exitant(hierarchy.patches()[p].element);
    std::transform(snapshot.exitant.begin() + std::ptrdiff_t(p * m),
                   snapshot.exitant.begin() + std::ptrdiff_t((p + 1) * m), row.begin(), scrub);
  }
  std::transform(snapshot.accumulated.begin(), snapshot.accumulated.end(),
                 tables.accumulated_irradiance().begin(), scrub);
  pull(hierarchy, tables);
}

// Zeroes the back bins of every patch: the asymmetric scheme's bounce starts with A = 0.
void clear_antiradiance(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                        RadianceTables& tables) {
  for (const Patch& patch : hierarchy.patches()) {
    const auto row = tables.exitant(patch.element);
    for (int j = 0; j < bins.bin_count(); ++j) {
      if (glm::dot(patch.normal, bins.direction(j)) <= 0.0f) row[size_t(j)] = glm::vec3(0.0f);
    }
  }
  pull(hierarchy, tables);
}

void symmetric_iteration(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                         const BinSpreading& spreading, const GlobalPass& transport,
                         RadianceTables& tables, const JobContext* context) {
  transport.run(spreading, tables, context);
  push(hierarchy, tables, context);
  local_pass(hierarchy, bins, tables, context);
  pull(hierarchy, tables, context);
}

// One bounce of the asymmetric scheme (derivation above). Precondition: the back bins hold the
// antiradiance to start from (0 after clear_antiradiance or the previous bounce).
void asymmetric_iteration(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                          const BinSpreading& spreading, const GlobalPass& transport,
                          RadianceTables& tables, const IterationOptions& options,
                          JobContext* context) {
  const int steps = std::max(options.antiradiance_steps, 1);
  bool incident_is_current = false;  // L_in = U (d − A) for the A now in the back bins
  for (int step = 0; step < steps; ++step) {
    if (context) context->throw_if_cancelled();
    transport.run(spreading, tables, context);
    push(hierarchy, tables, context);
    const double change = local_pass_antiradiance_only(hierarchy, bins, tables, context);
    pull(hierarchy, tables, context);
    // Unchanged A: the L_in just computed already belongs to it.
    if (change == 0.0) incident_is_current = true;
    if (change < options.tolerance) break;
  }
  if (!incident_is_current) {
    transport.run(spreading, tables, context);
    push(hierarchy, tables, context);
  }
  local_pass_radiance_only(hierarchy, bins, tables, context);
  pull(hierarchy, tables, context);
}

const char* scheme_name(IterationScheme scheme) {
  return scheme == IterationScheme::kSymmetric ? "symmetric" : "asymmetric";
}

}  // namespace

IterationResult iterate(const ElementHierarchy& hierarchy, const DirectionalBins& bins,
                        const BinSpreading& spreading, const GlobalPass& transport,
                        RadianceTables& tables, const IterationOptions& options,
                        JobContext* context) {
  if (tables.element_count() != hierarchy.element_count() ||
      tables.patch_count() != hierarchy.patch_count() || tables.bin_count() != bins.bin_count() ||
      transport.element_count() != hierarchy.element_count()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "iteration: tables or links do not match");
  }
  IterationResult result;
  IterationScheme scheme = options.scheme;
  const size_t max_iterations = size_t(std::max(options.max_iterations, 0));
  const int patience = std::max(options.growth_patience, 1);
  if (scheme == IterationScheme::kAsymmetric) clear_antiradiance(hierarchy, bins, tables);

  // The direct seed (the symmetric scheme's fallback restarts from it) and the last state
  // whose iteration did not grow.
  Snapshot initial, good;
  take(hierarchy, tables, 0, initial, context);
  take(hierarchy, tables, 0, good, context);  // = initial, copied in parallel with cancel
  std::vector<glm::vec3> before;
  int growing = 0;  // consecutive iterations whose added flux exceeded the previous one's
  double smallest_added = std::numeric_limits<double>::infinity();  // of the current scheme
  double previous_added = std::numeric_limits<double>::infinity();

  // At most one fallback, so at most 2 · max_iterations iterations run; the history (the
  // iterations that count) never exceeds max_iterations.
  while (result.history.size() < max_iterations) {
    if (context) {
      context->throw_if_cancelled();
      context->set_stage_progress(double(result.history.size()) / double(max_iterations));
    }
    const Clock::time_point start = Clock::now();
    const auto accumulated = tables.accumulated_irradiance();
    before.assign(accumulated.begin(), accumulated.end());
    if (scheme == IterationScheme::kSymmetric) {
      symmetric_iteration(hierarchy, bins, spreading, transport, tables, context);
    } else {
      asymmetric_iteration(hierarchy, bins, spreading, transport, tables, options, context);
    }
    for (size_t p = 0; p < before.size(); ++p) before[p] = accumulated[p] - before[p];
    const double added = flux(hierarchy, before);
    const double total = flux(hierarchy, accumulated);
    const bool is_finite = std::isfinite(added) && std::isfinite(total) &&
                           std::all_of(accumulated.begin(), accumulated.end(), finite);
    // Magnitudes: an iteration of the symmetric scheme may remove light (antiradiance
    // arriving one bounce late), so its added flux can be negative.
    const bool grew = std::abs(added) > previous_added;
    growing = grew ? growing + 1 : 0;
    // Light no closed scene of these albedos could hold (either sign: a large negative total
    // is over-cancelled light): the discretized transport creates energy.
    const bool over_bound = is_finite && std::abs(total) > options.flux_bound;
    // Growth that alternates with shrinking never grows `patience` times in a row: also
    // catch a bounce adding far more than the smallest one so far, while not converged.
    const bool residual_large = std::abs(added) > 10.0 * options.tolerance * std::abs(total);
    const bool surged = residual_large && std::abs(added) > kSurgeFactor * smallest_added;
    smallest_added = std::min(smallest_added, std::abs(added));

    if (!is_finite || over_bound || growing >= patience || surged) {
      const size_t failed_at = result.history.size() + 1;
      const std::string what = !is_finite   ? "turned non-finite"
                               : over_bound ? "exceeded the energy the lights allow"
                                            : "grew";
      if (scheme == IterationScheme::kSymmetric) {
        // Start the asymmetric scheme over from the direct seed: the symmetric iterates before
        // the failure may already carry the oscillation that grew (its added flux alternates
        // in sign, so growth shows late), and the asymmetric scheme converges from any start
        // only to the solution of the start's own bounces.
        restore(hierarchy, initial, tables);
        result.history.clear();
        scheme = IterationScheme::kAsymmetric;
        result.fell_back = true;
        result.warning = std::string("the symmetric iteration ") + what + " at iteration " +
                         std::to_string(failed_at) +
                         "; solved again with the asymmetric scheme (provably convergent, slower)";
        clear_antiradiance(hierarchy, bins, tables);
        good = initial;
        growing = 0;
        smallest_added = std::numeric_limits<double>::infinity();
        previous_added = result.history.empty() ? std::numeric_limits<double>::infinity()
                                                : std::abs(result.history.back().added_flux);
        continue;
      }
      // The asymmetric scheme converges for the continuous operators only; with too few
      // bins or too coarse patches it can grow as well. Keep the last state that did not.
      restore(hierarchy, good, tables);
      result.history.resize(good.history_size);
      result.stopped_early = true;
      result.warning += std::string(result.warning.empty() ? "" : "; ") +
                        "the asymmetric iteration " + what + " at iteration " +
                        std::to_string(failed_at) + "; kept the result of iteration " +
                        std::to_string(result.history.size()) +
                        " (more bins or smaller patches make the transport more accurate)";
      break;
    }

    IterationRecord record;
    record.iteration = int(result.history.size()) + 1;
    record.added_flux = added;
    record.residual = total != 0.0 ? std::abs(added) / std::abs(total) : (added == 0.0 ? 0 : 1);
    record.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.history.push_back(record);
    previous_added = std::abs(added);
    if (!grew) take(hierarchy, tables, result.history.size(), good, context);
    if (record.residual < options.tolerance) {
      result.converged = true;
      break;
    }
  }
  result.scheme_used = scheme;
  if (!result.converged && !result.stopped_early) {
    const std::string residual =
        result.history.empty() ? "none" : std::to_string(result.history.back().residual);
    result.warning += std::string(result.warning.empty() ? "" : "; ") + "the " +
                      scheme_name(scheme) + " iteration did not converge in " +
                      std::to_string(result.history.size()) + " iterations (residual " + residual +
                      ", tolerance " + std::to_string(options.tolerance) + ")";
  }
  if (context) context->set_stage_progress(1.0);
  return result;
}

}  // namespace bakegi::antiradiance
