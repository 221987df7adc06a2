// What the fuzzers share. bakegi's binary files end in a checksum of everything before it,
// so nearly every mutation of a seed would stop at "checksum mismatch" and the parsers
// behind it would never be reached. Each fuzzer therefore reads an input twice: as it is
// (the frame checks themselves) and with its frame made consistent (payload size and
// checksum recomputed), which drives the mutated payload into the section readers.
//
// A reader may refuse an input only with bakegi::Error; any other exception (bad_alloc from
// a size it trusted, out_of_range, ...) escapes the fuzzer and counts as a finding, as do
// the sanitizers' reports.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "util/byte_stream.h"
#include "util/error.h"
#include "util/framed_file.h"

namespace bakegi::fuzz {

// A copy of `bytes` whose u64 payload size (at `size_at`, counting the bytes between a
// `header_bytes` header and the 8-byte trailer) and trailing FNV-1a 64 checksum agree with
// its contents. Inputs too short to hold the frame come back unchanged.
inline std::vector<uint8_t> with_consistent_frame(std::span<const uint8_t> bytes, size_t size_at,
                                                  size_t header_bytes) {
  std::vector<uint8_t> fixed(bytes.begin(), bytes.end());
  if (fixed.size() < header_bytes + 8 || size_at + 8 > header_bytes) return fixed;
  const uint64_t payload = fixed.size() - header_bytes - 8;
  for (int i = 0; i < 8; ++i) fixed[size_at + i] = uint8_t(payload >> (8 * i));
  const size_t hashed = fixed.size() - 8;
  const uint64_t hash = fnv1a64(std::span<const uint8_t>(fixed.data(), hashed));
  for (int i = 0; i < 8; ++i) fixed[hashed + i] = uint8_t(hash >> (8 * i));
  return fixed;
}

// A framed file (util/framed_file.h: the .bgs and .bgl formats), read as it is and with its
// frame made consistent.
template <typename Read>
void read_framed_both_ways(std::span<const uint8_t> bytes, Read&& read) {
  read(bytes);
  read(with_consistent_frame(bytes, 16, kFramedHeaderBytes));
}

// What a reader accepted must read again after its own encoding: `read_again` throwing is a
// finding (abort), not a refusal.
template <typename ReadAgain>
void require_round_trip(ReadAgain&& read_again) {
  try {
    read_again();
  } catch (const Error&) {
    std::abort();
  }
}

// Runs `read` and swallows the refusals a reader is allowed to give.
template <typename Read>
void refused_or_read(Read&& read) {
  try {
    read();
  } catch (const Error&) {
  }
}

}  // namespace bakegi::fuzz
