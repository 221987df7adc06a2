// libFuzzer target: the precomputation cache reader (bake/precomputation_store.h) with the
// codec of every method that has one (meshless, antiradiance). The input's own key is the
// expected one, so that a mutated file gets past the key check into the codec's sections.
#include <memory>
#include <string>

#include "bake/precomputation_store.h"
#include "fuzz_input.h"
#include "solvers/method_registry.h"
#include "solvers/solver.h"

namespace {

// Cache header: 8-byte magic, u32 version, u32 reserved, u64 key high, u64 key low, u64
// payload bytes.
constexpr size_t kKeyAt = 16, kSizeAt = 32, kHeaderBytes = 40;

uint64_t u64_at(std::span<const uint8_t> bytes, size_t at) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t(bytes[at + i]) << (8 * i);
  return v;
}

void read_cache(const bakegi::PrecomputationCodec& codec, std::span<const uint8_t> bytes) {
  using namespace bakegi;
  CacheKey key;
  if (bytes.size() >= kHeaderBytes)
    key = CacheKey{u64_at(bytes, kKeyAt), u64_at(bytes, kKeyAt + 8)};
  fuzz::refused_or_read([&] { decode_cache_file(codec, bytes, key, "fuzz.bgcache"); });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The solvers live as long as the process: their codecs are what decode_cache_file uses.
  static const std::vector<std::unique_ptr<bakegi::Solver>> solvers = [] {
    std::vector<std::unique_ptr<bakegi::Solver>> made;
    for (const std::string& method : bakegi::method_names()) {
      std::unique_ptr<bakegi::Solver> solver = bakegi::make_solver(method);
      if (solver->codec()) made.push_back(std::move(solver));
    }
    return made;
  }();
  const std::span<const uint8_t> bytes(data, size);
  const std::vector<uint8_t> fixed =
      bakegi::fuzz::with_consistent_frame(bytes, kSizeAt, kHeaderBytes);
  for (const auto& solver : solvers) {
    read_cache(*solver->codec(), bytes);
    read_cache(*solver->codec(), fixed);
  }
  return 0;
}
