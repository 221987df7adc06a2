#include "util/file_bytes.h"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

#include "util/error.h"
#include "util/random.h"

namespace bakegi {

namespace {

// A name no other writer (thread, process) picks at the same time: the counter separates
// this process' writers, the thread id and the clock other processes'.
std::filesystem::path temporary_name(const std::filesystem::path& path) {
  static std::atomic<uint64_t> counter{0};
  const uint64_t unique =
      mix64(counter.fetch_add(1) ^ mix64(std::hash<std::thread::id>{}(std::this_thread::get_id())) ^
            mix64(uint64_t(std::chrono::steady_clock::now().time_since_epoch().count())));
  char suffix[24];
  std::snprintf(suffix, sizeof suffix, ".%016llx.tmp", static_cast<unsigned long long>(unique));
  std::filesystem::path temporary = path;
  temporary += suffix;
  return temporary;
}

}  // namespace

std::filesystem::path utf8_path(const std::string& text) {
  return std::filesystem::path(std::u8string(text.begin(), text.end()));
}

std::string utf8_text(const std::filesystem::path& path) {
  const std::u8string text = path.u8string();
  return std::string(text.begin(), text.end());
}

std::vector<uint8_t> read_file_bytes(const std::filesystem::path& path, uint64_t max_bytes) {
  const std::string name = utf8_text(path);
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
  const std::filesystem::path temporary = temporary_name(path);
  const std::string name = utf8_text(path), temporary_text = utf8_text(temporary);
  std::error_code ignored;
  try {
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw Error(BAKEGI_ERROR_IO,
                    "cannot write " + temporary_text + ": " + std::strerror(errno));
      }
      out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
      out.close();
      if (!out) {
        throw Error(BAKEGI_ERROR_IO,
                    "writing " + temporary_text + " failed: " + std::strerror(errno));
      }
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) {
      throw Error(BAKEGI_ERROR_IO,
                  "cannot rename " + temporary_text + " to " + name + ": " + error.message());
    }
  } catch (...) {
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

}  // namespace bakegi
