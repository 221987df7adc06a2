#include "solvers/antiradiance/global_pass.h"

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "util/error.h"

namespace bakegi::antiradiance {

namespace {

// Receivers per task: rows are 1–3 KB each, links per receiver vary widely, so small blocks
// keep the two workers balanced without noticeable scheduling cost.
constexpr size_t kReceiversPerBlock = 64;
// The grouping cuts the input into this many chunks, counted and scattered in parallel. A
// constant (not the thread count): the result is the stable order whatever the chunking, and
// the per-chunk counters cost chunks × elements × 4 bytes.
constexpr size_t kGroupingChunks = 16;
// How many links ahead the pass prefetches the sender's bin: the reads are scattered over the
// whole I_ex table (tens of MB), so without it every link waits for memory in turn.
constexpr uint32_t kPrefetchDistance = 16;

// Order of the links within a receiver: links that share spread class and bin are adjacent,
// so their transported intensities are summed before the filter is applied once.
bool link_order(const Link& a, const Link& b) {
  if (a.spread_class != b.spread_class) return a.spread_class < b.spread_class;
  if (a.bin != b.bin) return a.bin < b.bin;
  return a.sender < b.sender;
}

}  // namespace

GlobalPass::GlobalPass(std::vector<Link> links, size_t element_count, const BinSpreading& spreading)
    : element_count_(element_count), bin_count_(spreading.bin_count()) {
  if (links.size() > std::numeric_limits<uint32_t>::max()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "more than 2^32 links");
  }
  for (const Link& link : links) {
    if (link.receiver >= element_count || link.sender >= element_count) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "link element index out of range (" + std::to_string(link.receiver) + ", " +
                      std::to_string(link.sender) + " of " + std::to_string(element_count) + ")");
    }
    if (int(link.bin) >= spreading.bin_count() ||
        int(link.spread_class) >= spreading.class_count()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "link bin or spread class out of range");
    }
  }
  // Stable counting sort by receiver, in parallel over chunks of the input: chunk c's links of
  // receiver r go after those of chunks < c, which is the serial stable order.
  const size_t n = links.size();
  const size_t chunk = (n + kGroupingChunks - 1) / kGroupingChunks;
  std::vector<uint32_t> counts(kGroupingChunks * element_count, 0);
  auto chunk_range = [&](size_t c) {
    return std::pair<size_t, size_t>{std::min(n, c * chunk), std::min(n, (c + 1) * chunk)};
  };
  tbb::parallel_for(size_t(0), kGroupingChunks, [&](size_t c) {
    uint32_t* count = counts.data() + c * element_count;
    const auto [begin, end] = chunk_range(c);
    for (size_t l = begin; l < end; ++l) ++count[links[l].receiver];
  });
  receiver_offsets_.assign(element_count + 1, 0);
  uint32_t running = 0;
  for (size_t r = 0; r < element_count; ++r) {
    receiver_offsets_[r] = running;
    for (size_t c = 0; c < kGroupingChunks; ++c) {
      const uint32_t count = counts[c * element_count + r];
      counts[c * element_count + r] = running;  // now chunk c's next slot for r
      running += count;
    }
  }
  receiver_offsets_[element_count] = running;
  links_.resize(n);
  tbb::parallel_for(size_t(0), kGroupingChunks, [&](size_t c) {
    uint32_t* next = counts.data() + c * element_count;
    const auto [begin, end] = chunk_range(c);
    for (size_t l = begin; l < end; ++l) links_[next[links[l].receiver]++] = links[l];
  });
  std::vector<Link>().swap(links);
  // Within each receiver, by (class, bin, sender); stable, for duplicate links.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, element_count, kReceiversPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t r = block.begin(); r != block.end(); ++r) {
                        std::stable_sort(links_.begin() + receiver_offsets_[r],
                                         links_.begin() + receiver_offsets_[r + 1], link_order);
                      }
                    });
}

void GlobalPass::run(const BinSpreading& spreading, RadianceTables& tables,
                     const JobContext* context) const {
  if (tables.element_count() != element_count_ || tables.bin_count() != bin_count_ ||
      spreading.bin_count() != bin_count_) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "global pass: tables or spreading do not match the links");
  }
  if (element_count_ == 0) return;
  const size_t m = size_t(bin_count_);
  // Rows are contiguous (radiance_tables.h): the bin of a sender is one index away.
  const glm::vec3* const exitant = tables.exitant(0).data();
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, element_count_, kReceiversPerBlock),
      [&](const tbb::blocked_range<size_t>& block) {
        const uint32_t block_end = receiver_offsets_[block.end()];
        for (size_t receiver = block.begin(); receiver != block.end(); ++receiver) {
          // TBB may hand one task many blocks: check within, not only at its start.
          if (context && receiver % 64 == 0) context->throw_if_cancelled();
          const std::span<glm::vec3> incident = tables.incident(receiver);
          std::fill(incident.begin(), incident.end(), glm::vec3(0.0f));
          const uint32_t end = receiver_offsets_[receiver + 1];
          for (uint32_t l = receiver_offsets_[receiver]; l != end;) {
            // Links of one class and bin: sum what they transport, then spread it once.
            const uint8_t spread_class = links_[l].spread_class;
            const uint16_t bin = links_[l].bin;
            glm::vec3 transported(0.0f);
            do {
              if (l + kPrefetchDistance < block_end) {
                const Link& ahead = links_[l + kPrefetchDistance];
                __builtin_prefetch(exitant + size_t(ahead.sender) * m + ahead.bin);
              }
              const Link& link = links_[l];
              transported += link.form_factor * exitant[size_t(link.sender) * m + bin];
              ++l;
            } while (l != end && links_[l].bin == bin && links_[l].spread_class == spread_class);
            if (spread_class == 0) {
              incident[bin] += transported;  // the identity filter (weight 1)
              continue;
            }
            if (transported == glm::vec3(0.0f)) continue;
            const SpreadFilter filter = spreading.filter(spread_class, bin);
            for (size_t f = 0; f < filter.bins.size(); ++f) {
              incident[filter.bins[f]] += filter.weights[f] * transported;
            }
          }
        }
      });
}

size_t GlobalPass::memory_bytes() const {
  return links_.capacity() * sizeof(Link) + receiver_offsets_.capacity() * sizeof(uint32_t);
}

}  // namespace bakegi::antiradiance
