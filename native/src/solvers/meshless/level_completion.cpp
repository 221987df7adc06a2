#include "solvers/meshless/level_completion.h"

#include <bit>
#include <cstdint>

namespace bakegi::meshless {

uint32_t complete_missing_levels(const BasisHierarchy& basis, const VisibleRelations& relations,
                                 std::vector<BasisValue>& row) {
  // Levels are few (a handful); a bit mask of the ones present keeps this allocation-free.
  constexpr uint32_t kMaxLevels = 64;
  uint64_t present = 0;
  for (const BasisValue& b : row) {
    const uint32_t level = basis.point(b.index).level;
    if (level < kMaxLevels) present |= uint64_t(1) << level;
  }
  if (present == 0) return 0;
  const uint32_t finest = 63 - uint32_t(std::countl_zero(present));
  const uint64_t below = (uint64_t(1) << finest) - 1;
  const uint32_t missing = uint32_t(std::popcount(below & ~present));
  if (missing == 0) return 0;
  const size_t relation_rows =
      relations.coarser_offsets.empty() ? 0 : relations.coarser_offsets.size() - 1;
  // Keep the finest level's entries, in order, then add their coarser relations.
  size_t kept = 0;
  for (const BasisValue& b : row) {
    if (basis.point(b.index).level == finest) row[kept++] = b;
  }
  row.resize(kept);
  for (size_t e = 0; e < kept; ++e) {
    const BasisValue seen = row[e];
    if (seen.index >= relation_rows) continue;
    for (const BasisValue& coarse : relations.coarser_of(seen.index)) {
      row.push_back({coarse.index, seen.value * coarse.value});
    }
  }
  return missing;
}

}  // namespace bakegi::meshless
