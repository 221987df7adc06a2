// The frame around bakegi's checksummed binary files (the .bgs scene file, the .bgl
// lightmap layout): an 8-byte magic, u32 format version, u32 reserved (0), u64 payload
// bytes, the payload, then the u64 FNV-1a 64 hash of everything before it. One place
// writes and checks it, so that both formats refuse damage with the same messages.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "util/byte_stream.h"

namespace bakegi {

inline constexpr size_t kFramedHeaderBytes = 8 + 4 + 4 + 8;
inline constexpr size_t kFramedTrailerBytes = 8;

// A writer holding the header (payload size still 0): write the payload into it, then
// finish_framed_file.
ByteWriter begin_framed_file(const char (&magic)[8], uint32_t version);
// Patches the payload size, appends the checksum and returns the file's bytes.
std::vector<uint8_t> finish_framed_file(ByteWriter& writer);

struct FramedPayload {
  uint32_t version = 0;
  std::span<const uint8_t> payload;
};

// Checks magic, version (oldest..newest), size and checksum; throws Error(BAD_FILE)
// "<name>: ..." naming what is wrong ("not a bakegi <kind> (no BAKEGI header)", "format
// version N is not supported ...", "truncated or extended ...", "corrupt: checksum
// mismatch").
FramedPayload open_framed_file(std::span<const uint8_t> bytes, const char (&magic)[8],
                               uint32_t oldest, uint32_t newest, const std::string& kind,
                               const std::string& name);

}  // namespace bakegi
