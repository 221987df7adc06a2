// Little-endian binary writing and bounds-checked reading, and the FNV-1a 64 checksum,
// shared by the files the core writes (the .bgs scene file, the meshless precomputation
// cache) so that every format reads the same way and checks sizes the same way.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "util/bit_cast.h"
#include "util/error.h"

namespace bakegi {

inline uint64_t fnv1a64(std::span<const uint8_t> bytes) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (uint8_t b : bytes) {
    hash ^= b;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

// Little-endian writer, independent of the host's byte order.
class ByteWriter {
 public:
  std::vector<uint8_t> bytes;
  void u8(uint8_t v) { bytes.push_back(v); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void f32(float v) { u32(bakegi::bit_cast<uint32_t>(v)); }
  void f64(double v) { u64(bakegi::bit_cast<uint64_t>(v)); }
  void vec2(const glm::vec2& v) { f32(v.x), f32(v.y); }
  void vec3(const glm::vec3& v) { f32(v.x), f32(v.y), f32(v.z); }
  // u32 length, then the bytes.
  void string(const std::string& s) {
    u32(uint32_t(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void patch_u64(size_t at, uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes[at + i] = uint8_t(v >> (8 * i));
  }
  // Starts a section (u32 tag, u32 reserved, u64 size); returns where its size goes.
  size_t begin_section(uint32_t section_tag) {
    u32(section_tag);
    u32(0);
    const size_t at = bytes.size();
    u64(0);
    return at;
  }
  void end_section(size_t at) { patch_u64(at, bytes.size() - (at + 8)); }
};

// A section tag from four characters, first character in the lowest byte.
constexpr uint32_t section_tag(const char (&name)[5]) {
  return uint32_t(uint8_t(name[0])) | uint32_t(uint8_t(name[1])) << 8 |
         uint32_t(uint8_t(name[2])) << 16 | uint32_t(uint8_t(name[3])) << 24;
}

// Bounds-checked little-endian reader: every count is checked against the bytes left
// before anything is allocated for it. Failures throw Error(BAD_FILE) prefixed by `name`.
class ByteReader {
 public:
  ByteReader(std::span<const uint8_t> bytes, const std::string& name)
      : bytes_(bytes), name_(name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(BAKEGI_ERROR_BAD_FILE, name_ + ": " + what);
  }
  // Opens a section that ByteWriter::begin_section wrote, refusing another tag or a size past
  // the bytes left; returns where it ends, for close_section.
  size_t open_section(uint32_t expected_tag, const char* name) {
    const uint32_t tag = u32();
    u32();
    const uint64_t size = u64();
    if (tag != expected_tag) fail(std::string("corrupt: expected the ") + name + " section");
    need(size, 1, name);
    return position() + size;
  }
  // Refuses a section whose contents did not end where its size said.
  void close_section(size_t end, const char* name) const {
    if (position() != end) fail(std::string("corrupt: the ") + name + " section's size");
  }
  size_t left() const { return bytes_.size() - at_; }
  size_t position() const { return at_; }
  void need(uint64_t count, uint64_t element_bytes, const char* what) const {
    if (element_bytes != 0 && count > left() / element_bytes) {
      fail(std::string("truncated or corrupt: ") + what + " needs " + std::to_string(count) +
           " x " + std::to_string(element_bytes) + " bytes, " + std::to_string(left()) + " left");
    }
  }
  uint8_t u8() {
    need(1, 1, "a byte");
    return bytes_[at_++];
  }
  uint32_t u32() {
    need(1, 4, "a 32-bit value");
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(bytes_[at_++]) << (8 * i);
    return v;
  }
  uint64_t u64() {
    need(1, 8, "a 64-bit value");
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(bytes_[at_++]) << (8 * i);
    return v;
  }
  float f32() { return bakegi::bit_cast<float>(u32()); }
  double f64() { return bakegi::bit_cast<double>(u64()); }
  glm::vec2 vec2() {
    const float x = f32();
    return {x, f32()};
  }
  glm::vec3 vec3() {
    const float x = f32(), y = f32();
    return {x, y, f32()};
  }
  std::string string() {
    const uint32_t size = u32();
    need(size, 1, "a string");
    std::string s(reinterpret_cast<const char*>(bytes_.data() + at_), size);
    at_ += size;
    return s;
  }
  template <typename T, typename ReadOne>
  void array(std::vector<T>& out, uint64_t count, uint64_t element_bytes, const char* what,
             ReadOne read_one) {
    need(count, element_bytes, what);
    out.resize(count);
    for (T& element : out) element = read_one();
  }

 private:
  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
  std::string name_;
};

}  // namespace bakegi
