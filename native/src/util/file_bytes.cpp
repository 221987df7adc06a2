#include "util/file_bytes.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "atomic_file.h"
#include "util/error.h"

namespace bakegi {

std::filesystem::path utf8_path(const std::string& text) {
  return std::filesystem::path(std::u8string(text.begin(), text.end()));
}

std::string utf8_text(const std::filesystem::path& path) {
  const std::u8string text = path.u8string();
  return std::string(text.begin(), text.end());
}

std::vector<uint8_t> read_file_bytes(const std::filesystem::path& path, uint64_t max_bytes) {
  const std::string name = utf8_text(path);
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::is_directory(status)) {
    throw Error(BAKEGI_ERROR_IO, name + " is a folder, not a file");
  }
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    throw Error(BAKEGI_ERROR_IO, name + " is not a regular file");
  }
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(BAKEGI_ERROR_IO, "cannot open " + name + ": " + std::strerror(errno));
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error(BAKEGI_ERROR_IO, "cannot read " + name);
  if (uint64_t(size) > max_bytes) {
    throw Error(BAKEGI_ERROR_BAD_FILE, name + ": " + std::to_string(size) +
                                           " bytes, more than the " + std::to_string(max_bytes) +
                                           " allowed");
  }
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), size);
  if (!in) throw Error(BAKEGI_ERROR_IO, "reading " + name + " failed: " + std::strerror(errno));
  return bytes;
}

void write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes) {
  const std::string reason = write_file_atomically_or_reason(path, bytes);
  if (!reason.empty()) throw Error(BAKEGI_ERROR_IO, reason);
}

}  // namespace bakegi
