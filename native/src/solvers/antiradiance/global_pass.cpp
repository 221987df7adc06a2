#include "solvers/antiradiance/global_pass.h"

#include <algorithm>
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

}  // namespace

GlobalPass::GlobalPass(std::vector<Link> links, size_t element_count, const BinSpreading& spreading)
    : element_count_(element_count), bin_count_(spreading.bin_count()) {
  if (links.size() > std::numeric_limits<uint32_t>::max()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "more than 2^32 links");
  }
  receiver_offsets_.assign(element_count + 1, 0);
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
    ++receiver_offsets_[link.receiver + 1];
  }
  for (size_t i = 0; i < element_count; ++i) receiver_offsets_[i + 1] += receiver_offsets_[i];
  // Stable counting sort by receiver.
  links_.resize(links.size());
  std::vector<uint32_t> next(receiver_offsets_.begin(), receiver_offsets_.end() - 1);
  for (const Link& link : links) links_[next[link.receiver]++] = link;
}

void GlobalPass::run(const BinSpreading& spreading, RadianceTables& tables) const {
  if (tables.element_count() != element_count_ || tables.bin_count() != bin_count_ ||
      spreading.bin_count() != bin_count_) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "global pass: tables or spreading do not match the links");
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, element_count_, kReceiversPerBlock),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t receiver = block.begin(); receiver != block.end(); ++receiver) {
                        const std::span<glm::vec3> incident = tables.incident(receiver);
                        std::fill(incident.begin(), incident.end(), glm::vec3(0.0f));
                        for (uint32_t l = receiver_offsets_[receiver];
                             l != receiver_offsets_[receiver + 1]; ++l) {
                          const Link& link = links_[l];
                          const glm::vec3 transported =
                              link.form_factor * tables.exitant(link.sender)[link.bin];
                          const SpreadFilter filter = spreading.filter(link.spread_class, link.bin);
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
