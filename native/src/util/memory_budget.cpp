#include "util/memory_budget.h"

#include <cstdio>

namespace bakegi {

std::string MemoryBudget::megabytes(uint64_t bytes) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.1f MB", double(bytes) / double(1 << 20));
  return text;
}

}  // namespace bakegi
