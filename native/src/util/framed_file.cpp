#include "util/framed_file.h"

#include <cstring>
#include <iterator>

namespace bakegi {

ByteWriter begin_framed_file(const char (&magic)[8], uint32_t version) {
  ByteWriter w;
  w.bytes.reserve(kFramedHeaderBytes);  // (also spares GCC 12 a false -Wstringop-overflow)
  w.bytes.assign(std::begin(magic), std::end(magic));
  w.u32(version);
  w.u32(0);
  w.u64(0);  // payload size, patched by finish_framed_file
  return w;
}

std::vector<uint8_t> finish_framed_file(ByteWriter& writer) {
  writer.patch_u64(16, writer.bytes.size() - kFramedHeaderBytes);
  writer.u64(fnv1a64(writer.bytes));
  return std::move(writer.bytes);
}

FramedPayload open_framed_file(std::span<const uint8_t> bytes, const char (&magic)[8],
                               uint32_t oldest, uint32_t newest, const std::string& kind,
                               const std::string& name) {
  auto fail = [&](const std::string& what) -> void {
    throw Error(BAKEGI_ERROR_BAD_FILE, name + ": " + what);
  };
  if (bytes.size() < kFramedHeaderBytes + kFramedTrailerBytes ||
      std::memcmp(bytes.data(), magic, sizeof magic) != 0) {
    fail("not a bakegi " + kind + " (no BAKEGI header)");
  }
  ByteReader header(bytes.subspan(8, kFramedHeaderBytes - 8), name);
  FramedPayload framed;
  framed.version = header.u32();
  if (framed.version < oldest || framed.version > newest) {
    fail("format version " + std::to_string(framed.version) +
         " is not supported (this build reads " + std::to_string(oldest) + " to " +
         std::to_string(newest) + ")");
  }
  header.u32();
  const uint64_t payload_bytes = header.u64();
  const uint64_t held = bytes.size() - kFramedHeaderBytes - kFramedTrailerBytes;
  if (payload_bytes != held) {
    fail("truncated or extended: the header says " + std::to_string(payload_bytes) +
         " payload bytes, the file holds " + std::to_string(held));
  }
  const size_t hashed = bytes.size() - kFramedTrailerBytes;
  ByteReader trailer(bytes.subspan(hashed), name);
  if (trailer.u64() != fnv1a64(bytes.first(hashed))) fail("corrupt: checksum mismatch");
  framed.payload = bytes.subspan(kFramedHeaderBytes, payload_bytes);
  return framed;
}

}  // namespace bakegi
