// The cache folder's size cap (setting "cache_max_mb"): after a save the least recently
// used cache files beyond it are deleted, never the one just written, and nothing but
// *.bgcache files is touched.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "bake/precomputation_store.h"
#include "cache_test_support.h"

namespace bakegi::test {
namespace {

namespace fs = std::filesystem;

void write_bytes(const fs::path& path, size_t bytes, std::chrono::minutes age) {
  std::ofstream(path, std::ios::binary) << std::string(bytes, 'x');
  fs::last_write_time(path, fs::file_time_type::clock::now() - age);
}

TEST(CacheEviction, TheLeastRecentlyUsedGoFirstAndTheNewFileStays) {
  CacheFolder folder("bakegi_evict_");
  fs::create_directories(folder.path());
  const fs::path dir(folder.path());
  write_bytes(dir / "meshless-a.bgcache", 1000, std::chrono::minutes(50));  // oldest
  write_bytes(dir / "antiradiance-b.bgcache", 1000, std::chrono::minutes(40));
  write_bytes(dir / "meshless-c.bgcache", 1000, std::chrono::minutes(30));
  write_bytes(dir / "notes.txt", 5000, std::chrono::minutes(60));             // not a cache
  write_bytes(dir / "meshless-new.bgcache", 1000, std::chrono::minutes(90));  // just written
  // 4000 bytes of cache files, a cap of 2500: the two oldest others go.
  EXPECT_EQ(evict_least_recently_used(folder.path(), 2500, (dir / "meshless-new.bgcache").string()),
            2u);
  EXPECT_FALSE(fs::exists(dir / "meshless-a.bgcache"));
  EXPECT_FALSE(fs::exists(dir / "antiradiance-b.bgcache"));
  EXPECT_TRUE(fs::exists(dir / "meshless-c.bgcache"));
  EXPECT_TRUE(fs::exists(dir / "meshless-new.bgcache"));
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  // Within the cap, or no cap: nothing goes.
  EXPECT_EQ(evict_least_recently_used(folder.path(), 2500, ""), 0u);
  EXPECT_EQ(evict_least_recently_used(folder.path(), 0, ""), 0u);
  // A missing folder is no error.
  EXPECT_EQ(evict_least_recently_used(folder.path() + "/missing", 1, ""), 0u);
}

}  // namespace
}  // namespace bakegi::test
