// What the precomputation cache tests share (test_meshless_cache, test_antiradiance_cache):
// a bake's values and report, a fresh cache folder, file bytes in and out, the key and
// checksum of a cache file (bake/precomputation_store.h's layout).
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bake/precomputation_store.h"
#include "light_transport_fixtures.h"
#include "scene/bake_points.h"
#include "util/byte_stream.h"

namespace bakegi::test {

// Bake points on the floor and one wall of test::room_with_block (meshless_test_scenes.h),
// the room both cache tests bake: 200 points.
inline BakePoints room_points() {
  std::vector<glm::vec3> positions, normals;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      positions.push_back(glm::vec3(-0.9f + 0.2f * i, -0.9f + 0.2f * j, 0.0f));
      normals.push_back(glm::vec3(0, 0, 1));
      positions.push_back(glm::vec3(-1.0f, -0.9f + 0.2f * i, 0.1f + 0.2f * j));
      normals.push_back(glm::vec3(1, 0, 0));
    }
  }
  return make_points(positions, normals);
}

// A bake's values at its points and its report.
struct CachedBake {
  std::vector<glm::vec3> values;
  std::string report;  // JSON
  std::vector<std::string> warnings;

  bool says(const std::string& key, const std::string& value) const {
    return report.find("\"" + key + "\": \"" + value + "\"") != std::string::npos;
  }
  bool has(const std::string& key) const {
    return report.find("\"" + key + "\"") != std::string::npos;
  }
  // The text of a report key ("" when missing).
  std::string text_of(const std::string& key) const {
    const std::string quoted = "\"" + key + "\": \"";
    const size_t at = report.find(quoted);
    if (at == std::string::npos) return "";
    const size_t begin = at + quoted.size();
    return report.substr(begin, report.find('"', begin) - begin);
  }
  bool warned(const std::string& part) const {
    for (const std::string& w : warnings) {
      if (w.find(part) != std::string::npos) return true;
    }
    return false;
  }
};

inline void expect_same_values(const CachedBake& a, const CachedBake& b) {
  ASSERT_EQ(a.values.size(), b.values.size());
  for (size_t i = 0; i < a.values.size(); ++i) EXPECT_EQ(a.values[i], b.values[i]) << "point " << i;
}

// A fresh folder under the test temp directory, removed with everything in it at the end.
class CacheFolder {
 public:
  explicit CacheFolder(const std::string& prefix = "bakegi_cache_") {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::path(::testing::TempDir()) /
            (prefix + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) +
             "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
  }
  ~CacheFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::string path() const { return path_.string(); }
  size_t file_count() const {
    size_t n = 0;
    if (!std::filesystem::exists(path_)) return 0;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) {
      n += entry.is_regular_file() ? 1 : 0;
    }
    return n;
  }

 private:
  std::filesystem::path path_;
};

inline std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

inline void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// The key in a cache file's header (bytes 16..31).
inline CacheKey key_of(const std::vector<uint8_t>& file) {
  CacheKey key;
  for (int i = 0; i < 8; ++i) {
    key.high |= uint64_t(file[16 + i]) << (8 * i);
    key.low |= uint64_t(file[24 + i]) << (8 * i);
  }
  return key;
}

// Makes the trailer's checksum valid again after bytes were changed on purpose.
inline void recompute_checksum(std::vector<uint8_t>& file) {
  const uint64_t checksum = fnv1a64(std::span(file).first(file.size() - 8));
  for (int i = 0; i < 8; ++i) file[file.size() - 8 + i] = uint8_t(checksum >> (8 * i));
}

}  // namespace bakegi::test
