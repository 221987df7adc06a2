// libFuzzer target: the .bgl lightmap layout reader (lightmap/lightmap_layout_file.h),
// with the round trip the scene file fuzzer checks too.
#include <cstdlib>

#include "fuzz_input.h"
#include "lightmap/lightmap_layout_file.h"
#include "util/framed_file.h"

namespace {

void read_layout(std::span<const uint8_t> bytes) {
  using namespace bakegi;
  fuzz::refused_or_read([&] {
    const LightmapLayout layout = decode_lightmap_layout(bytes, "fuzz.bgl");
    try {
      decode_lightmap_layout(encode_lightmap_layout(layout), "re-encoded.bgl");
    } catch (const Error&) {
      std::abort();  // a layout that was read must survive its own encoding
    }
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const uint8_t> bytes(data, size);
  read_layout(bytes);
  read_layout(bakegi::fuzz::with_consistent_frame(bytes, 16, bakegi::kFramedHeaderBytes));
  return 0;
}
