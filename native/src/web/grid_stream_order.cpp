#include "web/grid_stream_order.h"

#include <algorithm>
#include <random>

namespace bakegi {

std::vector<uint32_t> grid_stream_order(const GridLayout& layout, uint64_t seed) {
  const auto& r = layout.resolution;
  const size_t count = layout.vertex_count();
  std::vector<uint32_t> order;
  order.reserve(count);
  std::vector<uint8_t> sent(count, 0);
  auto send = [&](uint32_t i, uint32_t j, uint32_t k) {
    const size_t v = layout.vertex_index(i, j, k);
    if (!sent[v]) sent[v] = 1, order.push_back(uint32_t(v));
  };
  for (uint32_t corner = 0; corner < 8; ++corner) {
    send(corner & 1 ? r[0] - 1 : 0, corner & 2 ? r[1] - 1 : 0, corner & 4 ? r[2] - 1 : 0);
  }
  const int axis = int(std::max_element(r.begin(), r.end()) - r.begin());
  uint32_t stride = 1;
  while (stride * 2 < r[axis]) stride *= 2;
  std::mt19937_64 random(seed);
  for (; stride >= 1; stride /= 2) {
    // The level's vertices, slice by slice along the longest axis.
    std::vector<std::vector<uint32_t>> slices(r[axis]);
    for (uint32_t k = 0; k < r[2]; k += stride) {
      for (uint32_t j = 0; j < r[1]; j += stride) {
        for (uint32_t i = 0; i < r[0]; i += stride) {
          const size_t v = layout.vertex_index(i, j, k);
          if (sent[v]) continue;
          const uint32_t along[3] = {i, j, k};
          slices[along[axis]].push_back(uint32_t(v));
        }
      }
    }
    for (auto& slice : slices) std::shuffle(slice.begin(), slice.end(), random);
    for (size_t taken = 0;; ++taken) {
      bool any = false;
      for (const auto& slice : slices) {
        if (taken < slice.size()) {
          any = true;
          sent[slice[taken]] = 1;
          order.push_back(slice[taken]);
        }
      }
      if (!any) break;
    }
  }
  return order;
}

}  // namespace bakegi
