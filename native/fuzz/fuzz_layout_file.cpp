// libFuzzer target: the .bgl lightmap layout reader (lightmap/lightmap_layout_file.h),
// with the round trip the scene file fuzzer checks too.
#include "fuzz_input.h"
#include "lightmap/lightmap_layout_file.h"

namespace {

void read_layout(std::span<const uint8_t> bytes) {
  using namespace bakegi;
  fuzz::refused_or_read([&] {
    const LightmapLayout layout = decode_lightmap_layout(bytes, "fuzz.bgl");
    fuzz::require_round_trip(
        [&] { decode_lightmap_layout(encode_lightmap_layout(layout), "re-encoded.bgl"); });
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bakegi::fuzz::read_framed_both_ways(std::span<const uint8_t>(data, size), read_layout);
  return 0;
}
