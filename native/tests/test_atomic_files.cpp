// Files bakegi writes are replaced whole or not at all, leftovers of killed writers are
// cleaned up, and reading a folder or a non-file says so (it used to report "out of memory").
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "atomic_file.h"
#include "cache_test_support.h"
#include "capi_test_scene.h"
#include "scene/scene_file.h"
#include "util/error.h"
#include "util/file_bytes.h"

namespace bakegi::test {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::vector<unsigned char> bytes_of(const std::string& text) {
  return std::vector<unsigned char>(text.begin(), text.end());
}

TEST(AtomicFiles, ReplacesTheTargetAndLeavesNoTemporary) {
  CacheFolder folder("bakegi_atomic_");
  fs::create_directories(folder.path());
  const fs::path target = fs::path(folder.path()) / "values.npy";
  write_text(target, "old");
  EXPECT_EQ(write_file_atomically_or_reason(target, bytes_of("new contents")), "");
  EXPECT_EQ(read_text(target), "new contents");
  EXPECT_EQ(folder.file_count(), 1u);
}

// A write that cannot finish (the target is a folder: the rename fails after the bytes were
// written) reports why, removes its temporary and leaves what was there.
TEST(AtomicFiles, AFailedWriteLeavesThePreviousFile) {
  CacheFolder folder("bakegi_atomic_");
  const fs::path target = fs::path(folder.path()) / "scene.bgs";
  fs::create_directories(target / "inside");
  const std::string reason = write_file_atomically_or_reason(target, bytes_of("x"));
  EXPECT_NE(reason.find("cannot rename"), std::string::npos) << reason;
  EXPECT_TRUE(fs::is_directory(target / "inside"));
  EXPECT_EQ(folder.file_count(), 0u);  // no temporary left beside it
  EXPECT_THROW(write_file_atomically(target, bytes_of("x")), Error);
}

// A writer killed mid-write leaves "<target>.<16 hex>.tmp" (or the EXR writer's former
// "<target>.tmp<pid>-<n>"); the next write to that target removes those older than any live
// write (10 minutes) and keeps younger ones (another process may be writing them now), and
// never touches files that only look similar.
TEST(AtomicFiles, AWriteRemovesStaleTemporariesOfItsTarget) {
  CacheFolder folder("bakegi_atomic_");
  fs::create_directories(folder.path());
  const fs::path dir(folder.path());
  const fs::path target = dir / "BakeGI_Lightmap_a.exr";
  const auto old = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (const char* name :
       {"BakeGI_Lightmap_a.exr.0123456789abcdef.tmp", "BakeGI_Lightmap_a.exr.tmp4242-7"}) {
    write_text(dir / name, "torn");
    fs::last_write_time(dir / name, old);
  }
  write_text(dir / "BakeGI_Lightmap_a.exr.fedcba9876543210.tmp", "being written");
  for (const char* name : {"BakeGI_Lightmap_a.exr.notes.tmp", "other.exr.0123456789abcdef.tmp"}) {
    write_text(dir / name, "keep");
    fs::last_write_time(dir / name, old);
  }
  EXPECT_EQ(write_file_atomically_or_reason(target, bytes_of("image")), "");
  EXPECT_FALSE(fs::exists(dir / "BakeGI_Lightmap_a.exr.0123456789abcdef.tmp"));
  EXPECT_FALSE(fs::exists(dir / "BakeGI_Lightmap_a.exr.tmp4242-7"));
  EXPECT_TRUE(fs::exists(dir / "BakeGI_Lightmap_a.exr.fedcba9876543210.tmp"));
  EXPECT_TRUE(fs::exists(dir / "BakeGI_Lightmap_a.exr.notes.tmp"));
  EXPECT_TRUE(fs::exists(dir / "other.exr.0123456789abcdef.tmp"));
  EXPECT_EQ(read_text(target), "image");
}

TEST(AtomicFiles, ReadingAFolderSaysSo) {
  CacheFolder folder("bakegi_atomic_");
  fs::create_directories(folder.path());
  try {
    read_scene_file(folder.path());
    FAIL() << "a folder was read as a scene file";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_IO);
    EXPECT_NE(std::string(e.what()).find("is a folder, not a file"), std::string::npos) << e.what();
  }
}

// The .bgs writer goes through the atomic write: the file it replaces is either the old
// scene or the new one, and no temporary remains.
TEST(AtomicFiles, SceneFilesAreWrittenAtomically) {
  CacheFolder folder("bakegi_atomic_");
  fs::create_directories(folder.path());
  const std::string path = (fs::path(folder.path()) / "box.bgs").string();
  write_text(path, "an older file");
  ScenePtr scene = new_box_scene();
  ASSERT_EQ(bakegi_file_write(path.c_str(), scene.get(), nullptr), BAKEGI_OK)
      << bakegi_last_error();
  EXPECT_EQ(read_scene_file(path).scene.meshes.size(), 1u);
  EXPECT_EQ(folder.file_count(), 1u);
}

}  // namespace
}  // namespace bakegi::test
