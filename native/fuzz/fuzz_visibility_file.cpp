// libFuzzer target: the web page's visibility volume reader (grid/grid_visibility_volume.h),
// with a round trip. The file says which grid it was made for; the fuzzer reads it against a
// grid of that resolution (up to 32 vertices an axis, so that a mutated header cannot ask
// for a huge grid), which is what the reader checks it against.
#include <cstring>

#include "fuzz_input.h"
#include "grid/grid_layout.h"
#include "grid/grid_visibility_volume.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace bakegi;
  if (size < 36) return 0;
  std::array<uint32_t, 3> resolution;
  for (int a = 0; a < 3; ++a) {
    std::memcpy(&resolution[a], data + 24 + 4 * a, 4);  // little-endian hosts
    if (resolution[a] < kMinGridResolution || resolution[a] > 32) return 0;
  }
  const GridLayout layout = make_grid_layout(glm::vec3(0.0f), glm::vec3(1.0f), resolution);
  fuzz::refused_or_read([&] {
    const GridVisibilityVolume volume =
        decode_visibility_file(std::span<const uint8_t>(data, size), layout);
    fuzz::require_round_trip(
        [&] { decode_visibility_file(encode_visibility_file(volume, layout), layout); });
  });
  return 0;
}
