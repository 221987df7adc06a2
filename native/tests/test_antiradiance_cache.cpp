// The antiradiance precomputation in the job's cache (bake/precomputation_store.h, the payload
// in antiradiance/precomputation_cache.h): a bake with "cache_dir" saves the hierarchy and
// links, a later bake of the same scene loads them and gives the same result; geometry,
// materials and the "shapes" settings change the key, lights and lighting settings do not;
// damaged files are detected and rebuilt; an unwritable folder only warns.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "bake/precomputation_store.h"
#include "bake/solver_run.h"
#include "cache_test_support.h"
#include "capi_test_scene.h"
#include "light_transport_fixtures.h"
#include "lights/direct_light.h"
#include "meshless_test_scenes.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "settings/settings.h"
#include "solvers/antiradiance/antiradiance_solver.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi {
namespace {

namespace fs = std::filesystem;
using test::CacheFolder;
using test::key_of;
using test::read_bytes;
using test::recompute_checksum;
using test::write_bytes;

// A closed room with a block and a point light (meshless_test_scenes.h).
SceneDescription room(glm::vec3 light, glm::vec3 block_albedo = glm::vec3(0.3f, 0.6f, 0.3f)) {
  return test::room_with_block(light, block_albedo);
}

const glm::vec3 kLight(0.5f, 0.2f, 1.8f);

using test::room_points;

// Coarse and cheap (a cached bake runs several solves): what is tested is that a loaded
// precomputation is the saved one, not its quality. About 250 patches, 48 bins.
Settings small_settings(const std::string& cache_dir) {
  Settings settings;
  settings.set("bins", int64_t(48));
  settings.set("patch_size", 0.75);
  settings.set("direct_samples", int64_t(16));
  settings.set("near_field_rays", int64_t(32));
  if (!cache_dir.empty()) settings.set("cache_dir", cache_dir);
  return settings;
}

struct Bake : test::CachedBake {
  uint64_t links = 0;
  uint64_t patches = 0;
  std::string cache_path() const { return text_of("antiradiance_cache_path"); }
};

const PrecomputationCodec& codec() {
  static const AntiradianceSolver solver;
  return *solver.codec();
}

// Solves and evaluates at the points, as a bake job does.
Bake bake(const SceneDescription& description, const BakePoints& points,
          const Settings& settings) {
  const Scene scene = build_scene(description);
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  AntiradianceSolver solver;
  JobContext context;
  const SolveInputs inputs{scene, tracer, direct, settings, &points};
  const auto field = run_solver(solver, "antiradiance", inputs, context).field;
  Bake result;
  result.values.resize(points.size());
  field->evaluate(points, result.values, context);
  result.report = context.report().to_json();
  result.warnings = context.report().warnings();
  result.links = context.report().count("antiradiance_links");
  result.patches = context.report().count("antiradiance_patches");
  return result;
}

TEST(AntiradianceCache, SecondBakeLoadsTheFileAndGivesTheSameResult) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake first = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(first.says("antiradiance_cache", "miss")) << first.report;
  const std::string path = first.cache_path();
  ASSERT_FALSE(path.empty());
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(fs::path(path).filename().string().size(),
            std::string("antiradiance-.bgcache").size() + 16);
  EXPECT_EQ(folder.file_count(), 1u);  // no temporary file left behind
  EXPECT_TRUE(first.has("antiradiance_linking")) << first.report;
  EXPECT_GT(first.links, 0u);
  EXPECT_TRUE(first.warnings.empty());

  const Bake second = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(second.says("antiradiance_cache", "hit")) << second.report;
  EXPECT_EQ(second.cache_path(), path);
  // Nothing was linked (as in a relight, no linking time) and the hierarchy was not built; the
  // counts light() reports come from the loaded precomputation.
  EXPECT_FALSE(second.has("antiradiance_linking")) << second.report;
  EXPECT_FALSE(second.has("antiradiance_hierarchy")) << second.report;
  EXPECT_EQ(second.links, first.links);
  EXPECT_EQ(second.patches, first.patches);
  EXPECT_TRUE(second.has("antiradiance_cache_load"));
  EXPECT_TRUE(second.has("antiradiance_cache_precompute_seconds"));
  EXPECT_TRUE(second.warnings.empty());
  // The same hierarchy, links (in the same order) and bins: bit for bit the same result.
  expect_same_values(first, second);
}

TEST(AntiradianceCache, ChangedAlbedoOrMovedVertexMissesWithANewFile) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake base = bake(room(kLight), points, small_settings(folder.path()));
  ASSERT_TRUE(base.says("antiradiance_cache", "miss"));

  const Bake albedo =
      bake(room(kLight, glm::vec3(0.3f, 0.6f, 0.31f)), points, small_settings(folder.path()));
  EXPECT_TRUE(albedo.says("antiradiance_cache", "miss")) << albedo.report;
  EXPECT_NE(albedo.cache_path(), base.cache_path());

  SceneDescription moved = room(kLight);
  moved.meshes[1].positions[0] += glm::vec3(0.0f, 0.0f, 0.01f);
  const Bake vertex = bake(moved, points, small_settings(folder.path()));
  EXPECT_TRUE(vertex.says("antiradiance_cache", "miss")) << vertex.report;
  EXPECT_NE(vertex.cache_path(), base.cache_path());
  EXPECT_NE(vertex.cache_path(), albedo.cache_path());
  EXPECT_EQ(folder.file_count(), 3u);
}

TEST(AntiradianceCache, ShapesSettingsMissLightingSettingsHit) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake base = bake(room(kLight), points, small_settings(folder.path()));
  ASSERT_TRUE(base.says("antiradiance_cache", "miss"));

  Settings more_bins = small_settings(folder.path());
  more_bins.set("bins", int64_t(108));
  const Bake binned = bake(room(kLight), points, more_bins);
  EXPECT_TRUE(binned.says("antiradiance_cache", "miss")) << binned.report;
  EXPECT_NE(binned.cache_path(), base.cache_path());

  // Lighting settings are read again by light(): a hit gives what a fresh bake gives.
  Settings relit = small_settings(folder.path());
  relit.set("iterations", int64_t(3));
  relit.set("seed", int64_t(5));
  const Bake hit = bake(room(kLight), points, relit);
  EXPECT_TRUE(hit.says("antiradiance_cache", "hit")) << hit.report;
  EXPECT_EQ(hit.cache_path(), base.cache_path());
  Settings fresh_settings = small_settings("");
  fresh_settings.set("iterations", int64_t(3));
  fresh_settings.set("seed", int64_t(5));
  expect_same_values(hit, bake(room(kLight), points, fresh_settings));
  EXPECT_NE(hit.values, base.values);  // the settings did change the result
}

TEST(AntiradianceCache, MovedLightHitsAndEqualsAFreshBakeWithTheMovedLight) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const glm::vec3 moved_light(-0.6f, -0.4f, 1.5f);
  const Bake first = bake(room(kLight), points, small_settings(folder.path()));
  ASSERT_TRUE(first.says("antiradiance_cache", "miss"));
  const Bake relit = bake(room(moved_light), points, small_settings(folder.path()));
  EXPECT_TRUE(relit.says("antiradiance_cache", "hit")) << relit.report;
  const Bake fresh = bake(room(moved_light), points, small_settings(""));
  EXPECT_TRUE(fresh.says("antiradiance_cache", "off"));
  // Hierarchy and links do not depend on the lights (§3.3), so loading them is exactly a full
  // bake.
  expect_same_values(relit, fresh);
  double total = 0.0;
  for (const glm::vec3& v : relit.values) total += v.x;
  EXPECT_GT(total, 0.0);
  EXPECT_NE(relit.values, first.values);  // the light did move
}

// An open mesh gets back sides and a warning from precompute(); a hit repeats the warning.
TEST(AntiradianceCache, AHitRepeatsThePrecomputationsWarnings) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  SceneDescription scene = room(kLight);
  test::add_quad(scene, glm::vec3(0.6f, 0.6f, 1.0f), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0),
                 0.2f, 0.2f, 0);
  const Bake first = bake(scene, points, small_settings(folder.path()));
  ASSERT_TRUE(first.says("antiradiance_cache", "miss"));
  ASSERT_TRUE(first.warned("do not bound a solid")) << first.report;
  const Bake second = bake(scene, points, small_settings(folder.path()));
  EXPECT_TRUE(second.says("antiradiance_cache", "hit")) << second.report;
  EXPECT_EQ(second.warnings, first.warnings);
  expect_same_values(first, second);
}

TEST(AntiradianceCache, CorruptOrTruncatedFileIsDetectedAndRebuilt) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake fresh = bake(room(kLight), points, small_settings(folder.path()));
  const std::string path = fresh.cache_path();
  const std::vector<uint8_t> good = read_bytes(path);
  ASSERT_GT(good.size(), 200u);

  // One flipped byte in the payload (the links are the bulk of it): the checksum catches it.
  std::vector<uint8_t> flipped = good;
  flipped[flipped.size() * 3 / 4] ^= 0x5a;
  write_bytes(path, flipped);
  const Bake after_flip = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(after_flip.says("antiradiance_cache", "stale")) << after_flip.report;
  EXPECT_TRUE(after_flip.warned("was stale/corrupt")) << after_flip.report;
  EXPECT_TRUE(after_flip.has("antiradiance_linking"));  // rebuilt
  expect_same_values(after_flip, fresh);
  // Rebuilt and overwritten (the same size; the bytes differ in the precompute's seconds).
  EXPECT_EQ(read_bytes(path).size(), good.size());

  // Cut short (as a crash during a non-atomic write would leave it).
  write_bytes(path, std::vector<uint8_t>(good.begin(), good.begin() + good.size() / 2));
  const Bake after_cut = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(after_cut.says("antiradiance_cache", "stale")) << after_cut.report;
  EXPECT_TRUE(after_cut.warned("was stale/corrupt"));
  expect_same_values(after_cut, fresh);

  const Bake again = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(again.says("antiradiance_cache", "hit")) << again.report;
  expect_same_values(again, fresh);
}

TEST(AntiradianceCache, HugeCountsWithAValidChecksumAreRefusedBeforeAllocating) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake fresh = bake(room(kLight), points, small_settings(folder.path()));
  const std::vector<uint8_t> good = read_bytes(fresh.cache_path());
  // Layout (precomputation_cache.h): a 40-byte header, then STAT and HIER (a 16-byte section
  // header and its data each), then ELEM whose first u64 is the element count.
  auto section_size = [&](size_t at) {
    uint64_t size = 0;
    for (int i = 0; i < 8; ++i) size |= uint64_t(good[at + 8 + i]) << (8 * i);
    return size;
  };
  const size_t hier_at = 40 + 16 + section_size(40);
  const size_t count_at = hier_at + 16 + section_size(hier_at) + 16;
  ASSERT_LT(count_at + 8, good.size());

  // A crafted file, not a random corruption: the checksum is recomputed so that only the
  // size checks stand between the count (2^40 elements, 68 TiB) and an allocation.
  std::vector<uint8_t> crafted = good;
  for (int i = 0; i < 8; ++i) crafted[count_at + i] = uint8_t((uint64_t(1) << 40) >> (8 * i));
  recompute_checksum(crafted);
  const CacheKey key = key_of(good);
  EXPECT_NO_THROW(decode_cache_file(codec(), good, key, "good"));
  try {
    decode_cache_file(codec(), crafted, key, "crafted");
    ADD_FAILURE() << "a count beyond the file was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
    EXPECT_NE(std::string(e.what()).find("elements"), std::string::npos) << e.what();
  }
}

// Damage that a checksum cannot catch (a forged or miscomputed trailer): any byte changed,
// checksum made valid again, must give either a loaded precomputation or Error(BAD_FILE),
// never a crash, an out-of-range read or a huge allocation (this code runs inside Blender;
// the sanitizer build checks the reads). What loads is lit too: light() must not index past
// anything either (it may refuse, or warn of a diverging iteration).
TEST(AntiradianceCache, ForgedBytesWithAValidChecksumNeverCrash) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Settings settings = small_settings(folder.path());
  const Bake fresh = bake(room(kLight), points, settings);
  const std::vector<uint8_t> good = read_bytes(fresh.cache_path());
  const CacheKey key = key_of(good);

  const Scene scene = build_scene(room(kLight));
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  const SolveInputs inputs{scene, tracer, direct, settings, &points};
  AntiradianceSolver solver;
  std::mt19937_64 random(7);
  int refused = 0, lit = 0;
  constexpr int kTrials = 100;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<uint8_t> forged = good;
    // Half the trials in the first 2 KiB (header, statistics, counts, the tree's top), half
    // anywhere.
    const size_t span = trial % 2 == 0 ? std::min<size_t>(2048, good.size() - 8) : good.size() - 8;
    const size_t at = random() % span;
    forged[at] ^= uint8_t(1 + random() % 255);
    recompute_checksum(forged);
    std::shared_ptr<const Precomputation> loaded;
    try {
      loaded = decode_cache_file(codec(), forged, key, "forged");
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE) << "byte " << at << ": " << e.what();
      ++refused;
      continue;
    }
    JobContext context;
    try {
      const auto field = solver.light(inputs, loaded, context);
      std::vector<glm::vec3> values(points.size());
      field->evaluate(points, values, context);
      ++lit;
    } catch (const Error&) {
      // A refusal is fine; a crash is not.
    }
  }
  // Many bytes are coordinates and form factors, which any finite float may hold, so many
  // forgeries load; but the header, counts and indices are checked, so some must be refused.
  EXPECT_GT(refused, 0);
  EXPECT_GT(lit, 0);
}

TEST(AntiradianceCache, UnwritableFolderWarnsAndStillBakes) {
  const CacheFolder folder;
  fs::create_directories(folder.path());
  // A folder inside a regular file cannot be created, whatever the user's permissions.
  const std::string blocker = folder.path() + "/a_file";
  write_bytes(blocker, {1, 2, 3});
  const BakePoints points = room_points();
  const Bake cached = bake(room(kLight), points, small_settings(blocker + "/cache"));
  EXPECT_TRUE(cached.says("antiradiance_cache", "miss")) << cached.report;
  EXPECT_TRUE(cached.warned("not saved")) << cached.report;
  const Bake plain = bake(room(kLight), points, small_settings(""));
  expect_same_values(cached, plain);
}

std::string job_report(const bakegi_job* job) {
  size_t size = 0;
  EXPECT_EQ(bakegi_job_get_report(job, nullptr, 0, &size), BAKEGI_OK);
  std::string report(size + 1, '\0');  // room for the NUL
  EXPECT_EQ(bakegi_job_get_report(job, report.data(), report.size(), &size), BAKEGI_OK);
  report.resize(size);
  return report;
}

// Through the C API: "cache_dir" is a known setting, and the second job loads the file.
TEST(AntiradianceCache, JobsThroughTheCApiSaveAndLoad) {
  const CacheFolder folder;
  const test::ScenePtr scene = test::new_box_scene();
  constexpr size_t kCount = 16;
  const test::PointsPtr points = test::new_floor_points(kCount);
  const test::SettingsPtr settings = test::new_settings("antiradiance");
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "bins", 48), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_string(settings.get(), "cache_dir", folder.path().c_str()),
            BAKEGI_OK);
  std::vector<float> results[2];
  std::string reports[2];
  for (int run = 0; run < 2; ++run) {
    bakegi_job* raw = nullptr;
    ASSERT_EQ(bakegi_job_start(scene.get(), points.get(), settings.get(), &raw), BAKEGI_OK)
        << test::last_error();
    const test::JobPtr job(raw);
    ASSERT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << test::last_error();
    results[run].resize(3 * kCount);
    ASSERT_EQ(bakegi_job_get_result(job.get(), results[run].data(), kCount), BAKEGI_OK);
    reports[run] = job_report(job.get());
  }
  EXPECT_NE(reports[0].find("\"antiradiance_cache\": \"miss\""), std::string::npos) << reports[0];
  EXPECT_NE(reports[1].find("\"antiradiance_cache\": \"hit\""), std::string::npos) << reports[1];
  EXPECT_EQ(results[0], results[1]);
  EXPECT_EQ(folder.file_count(), 1u);
}

}  // namespace
}  // namespace bakegi
