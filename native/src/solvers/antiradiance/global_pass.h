// The global pass of Antiradiance (§3.1, §4.2): operator U, the unoccluded transport of
// exitant intensity I_ex = I_L − I_A along the links into incident radiance L_in.
//
// For every link (receiver i, sender k, bin j, form factor F = 1 / (|x_i − x_k|² ω_bin)),
// Eq. 16 with the spreading of Fig. 8: the energy is taken from the sender's bin of the center
// direction and spread over the receiver's bins around it,
//
//   L_in(i, b) += w_b · F · I_ex(k, j)   for (b, w_b) in BinSpreading::filter(class, j).
//
// L_in is cleared first (only exchanges of this pass are in it). Links are grouped by receiver
// once, at construction (a stable counting sort), and sorted within a receiver by (spread
// class, bin, sender): each receiver's row is then written by one task in that fixed order, so
// the result is free of races and bit-identical for any thread count. Links of a receiver that
// share class and bin have their F · I_ex summed first and the filter applied once (the same
// sum, fewer bin updates); the senders' bins are prefetched a few links ahead, since they are
// scattered over the whole I_ex table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/link.h"
#include "solvers/antiradiance/radiance_tables.h"
#include "util/job_context.h"

namespace bakegi::antiradiance {

class GlobalPass {
 public:
  GlobalPass() = default;
  // Takes the links (move them in: the pass keeps the only copy, grouped by receiver).
  // Throws Error(INVALID_ARGUMENT) for a link whose element index is not below
  // `element_count` or whose bin or spread class is outside `spreading`.
  GlobalPass(std::vector<Link> links, size_t element_count, const BinSpreading& spreading);

  // L_in = U I_ex for every element. Throws Error(INVALID_ARGUMENT) when the tables' element
  // or bin count differs from the one the links were built for.
  // `context` (optional) is checked for cancel every block of receivers: at 768 bins one
  // pass takes about half a second, too long to wait for between iterations.
  void run(const BinSpreading& spreading, RadianceTables& tables,
           const JobContext* context = nullptr) const;

  // The links grouped by receiver (ascending), by (spread class, bin, sender) within a
  // receiver, input order kept among equal keys.
  std::span<const Link> links() const { return links_; }
  size_t element_count() const { return element_count_; }
  size_t memory_bytes() const;

 private:
  // The precomputation cache (precomputation_cache.cpp) writes and reads every member.
  friend struct PrecomputationCacheAccess;

  std::vector<Link> links_;
  std::vector<uint32_t> receiver_offsets_;  // element_count_ + 1 entries into links_
  size_t element_count_ = 0;
  int bin_count_ = 0;
};

}  // namespace bakegi::antiradiance
