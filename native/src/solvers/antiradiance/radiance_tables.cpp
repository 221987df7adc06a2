#include "solvers/antiradiance/radiance_tables.h"

#include <algorithm>
#include <limits>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace bakegi::antiradiance {

namespace {

uint64_t saturating_multiply(uint64_t a, uint64_t b) {
  if (a != 0 && b > std::numeric_limits<uint64_t>::max() / a) {
    return std::numeric_limits<uint64_t>::max();
  }
  return a * b;
}

uint64_t saturating_add(uint64_t a, uint64_t b) {
  return b > std::numeric_limits<uint64_t>::max() - a ? std::numeric_limits<uint64_t>::max()
                                                      : a + b;
}

// Transparent huge pages are 2 MiB on x86-64 and most aarch64 kernels.
constexpr size_t kHugePageBytes = size_t(2) << 20;
// Smaller tables gain nothing from huge pages and would waste most of one.
constexpr size_t kHugePageMinimumBytes = 4 * kHugePageBytes;

size_t rounded_to_huge_pages(size_t bytes) {
  return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
}

}  // namespace

template <class T>
void* HugePageAllocator<T>::allocate_bytes(size_t bytes) {
  if (bytes < kHugePageMinimumBytes) {
    return ::operator new(bytes, std::align_val_t(alignof(T)));
  }
  void* p = ::operator new(rounded_to_huge_pages(bytes), std::align_val_t(kHugePageBytes));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Advice only: a refusal leaves ordinary pages, which is still correct.
  madvise(p, rounded_to_huge_pages(bytes), MADV_HUGEPAGE);
#endif
  return p;
}

template <class T>
void HugePageAllocator<T>::deallocate_bytes(void* p, size_t bytes) {
  if (bytes < kHugePageMinimumBytes) {
    ::operator delete(p, std::align_val_t(alignof(T)));
  } else {
    ::operator delete(p, std::align_val_t(kHugePageBytes));
  }
}

template struct HugePageAllocator<glm::vec3>;

uint64_t RadianceTables::bytes(uint64_t elements, uint64_t patches, uint64_t bins) {
  const uint64_t per_table =
      saturating_multiply(saturating_multiply(elements, bins), sizeof(glm::vec3));
  return saturating_add(saturating_multiply(per_table, 2),
                        saturating_multiply(patches, sizeof(glm::vec3)));
}

RadianceTables::RadianceTables(size_t element_count, size_t patch_count, int bin_count)
    : element_count_(element_count),
      bin_count_(std::max(bin_count, 0)),
      exitant_(element_count * size_t(bin_count_), glm::vec3(0.0f)),
      incident_(element_count * size_t(bin_count_), glm::vec3(0.0f)),
      accumulated_irradiance_(patch_count, glm::vec3(0.0f)) {}

void RadianceTables::clear() {
  std::fill(exitant_.begin(), exitant_.end(), glm::vec3(0.0f));
  std::fill(incident_.begin(), incident_.end(), glm::vec3(0.0f));
  std::fill(accumulated_irradiance_.begin(), accumulated_irradiance_.end(), glm::vec3(0.0f));
}

size_t RadianceTables::memory_bytes() const {
  return (exitant_.capacity() + incident_.capacity() + accumulated_irradiance_.capacity()) *
         sizeof(glm::vec3);
}

}  // namespace bakegi::antiradiance
