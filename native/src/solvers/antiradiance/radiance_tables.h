// The per-element bin tables of Antiradiance (§3.1, §4.1): exitant intensity I_ex = I_L − I_A
// (W/sr) and incident radiance L_in (W/(m² sr)), n_elements rows of m bins each, RGB; plus the
// per-patch output, the indirect irradiance accumulated over the iterations.
//
// Bins are the direction light TRAVELS (link.h): I_ex(x, ω_j) leaves x along ω_j and
// L_in(x, ω_j) arrives at x travelling along ω_j.
//
// Memory: each table is elements × m × 12 bytes (three floats per bin). For the Cornell box
// default (26,623 elements) at 192 bins that is 61 MB per table, 123 MB for both; call bytes()
// against a budget BEFORE constructing. The paper's third table I_total is replaced by the
// per-patch irradiance E_acc (the output is diffuse irradiance, so one vec3 per patch suffices).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi::antiradiance {

// Allocates the bin tables on 2 MiB boundaries and, on Linux, asks for transparent huge pages
// before the memory is first touched: the global pass reads one bin of a sender row scattered
// over the whole I_ex table (tens of MB), and with 4 KiB pages nearly every such read also
// misses the TLB. Elsewhere (or when the kernel declines) it is an ordinary aligned allocation.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(allocate_bytes(n * sizeof(T))); }
  void deallocate(T* p, size_t n) { deallocate_bytes(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }

  static void* allocate_bytes(size_t bytes);
  static void deallocate_bytes(void* p, size_t bytes);
};

class RadianceTables {
 public:
  // Bytes the tables of `elements` × `bins` plus `patches` accumulators take (saturates at
  // UINT64_MAX), to check a memory budget before allocating.
  static uint64_t bytes(uint64_t elements, uint64_t patches, uint64_t bins);

  RadianceTables() = default;
  // All entries zero.
  RadianceTables(size_t element_count, size_t patch_count, int bin_count);

  size_t element_count() const { return element_count_; }
  size_t patch_count() const { return accumulated_irradiance_.size(); }
  int bin_count() const { return bin_count_; }

  // Row of `element`: m bins.
  std::span<glm::vec3> exitant(size_t element) { return row(exitant_, element); }
  std::span<const glm::vec3> exitant(size_t element) const { return row(exitant_, element); }
  std::span<glm::vec3> incident(size_t element) { return row(incident_, element); }
  std::span<const glm::vec3> incident(size_t element) const { return row(incident_, element); }

  // Indirect irradiance (W/m²) per patch (ElementHierarchy::patches() order), summed over
  // local passes.
  std::span<glm::vec3> accumulated_irradiance() { return accumulated_irradiance_; }
  std::span<const glm::vec3> accumulated_irradiance() const { return accumulated_irradiance_; }

  // Zeroes every table.
  void clear();

  size_t memory_bytes() const;

 private:
  template <class Table>
  std::span<glm::vec3> row(Table& table, size_t element) {
    return {table.data() + element * size_t(bin_count_), size_t(bin_count_)};
  }
  template <class Table>
  std::span<const glm::vec3> row(const Table& table, size_t element) const {
    return {table.data() + element * size_t(bin_count_), size_t(bin_count_)};
  }

  size_t element_count_ = 0;
  int bin_count_ = 0;
  using Table = std::vector<glm::vec3, HugePageAllocator<glm::vec3>>;
  Table exitant_;   // I_ex, element-major
  Table incident_;  // L_in, element-major
  std::vector<glm::vec3> accumulated_irradiance_;
};

}  // namespace bakegi::antiradiance
