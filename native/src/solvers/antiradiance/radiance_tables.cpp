#include "solvers/antiradiance/radiance_tables.h"

#include <algorithm>
#include <limits>

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

}  // namespace

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
