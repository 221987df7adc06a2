// libFuzzer target: the .bgs scene file reader (scene/scene_file.h), then what the C API does
// with a scene it read (every element checked, the scene flattened), then a round trip: a
// file that was read must encode to one that reads again.
#include "fuzz_input.h"
#include "scene/scene_file.h"
#include "scene/scene_validation.h"

namespace {

// Flattening copies triangles: keep a fuzzed scene's copy small (the reader already bounds
// every count by the bytes it holds, so this only skips the slow path, never a check).
constexpr size_t kMaxFlattenedBytes = size_t(64) << 20;

void read_scene(std::span<const uint8_t> bytes) {
  using namespace bakegi;
  fuzz::refused_or_read([&] {
    const SceneFile file = decode_scene_file(bytes, "fuzz.bgs");
    const std::vector<uint8_t> again =
        encode_scene_file(file.scene, file.points ? &*file.points : nullptr);
    fuzz::require_round_trip([&] { decode_scene_file(again, "re-encoded.bgs"); });
    if (estimate_scene_bytes(file.scene) <= kMaxFlattenedBytes) build_scene(file.scene);
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bakegi::fuzz::read_framed_both_ways(std::span<const uint8_t>(data, size), read_scene);
  return 0;
}
