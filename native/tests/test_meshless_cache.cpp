// The meshless precomputation in the job's cache (bake/precomputation_store.h, the payload in
// meshless/precomputation_cache.h): a bake with
// "cache_dir" saves the precomputation, a later bake of the same scene loads it and gives the
// same result; anything that shapes the precomputation changes the key; damaged files are
// detected and rebuilt; lights are not part of the key; an unwritable folder only warns.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
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
#include "solvers/meshless/meshless_solver.h"
#include "solvers/meshless/precomputation_cache.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/job_context.h"

namespace bakegi {
namespace {

namespace fs = std::filesystem;
using test::CacheFolder;
using test::read_bytes;
using test::write_bytes;

// A closed room with a block and a point light; bake points on the floor and one wall.
SceneDescription room(glm::vec3 light, glm::vec3 block_albedo = glm::vec3(0.3f, 0.6f, 0.3f)) {
  return test::room_with_block(light, block_albedo);
}

const glm::vec3 kLight(0.5f, 0.2f, 1.8f);

using test::room_points;

// Coarse and cheap (a cached bake runs several solves): what is tested is that a loaded
// precomputation is the saved one, not its quality.
Settings small_settings(const std::string& cache_dir) {
  Settings settings;
  settings.set("levels", int64_t(2));
  settings.set("coarse_spacing", 0.5);
  settings.set("gather_rays", int64_t(16));
  settings.set("bounces", int64_t(3));
  if (!cache_dir.empty()) settings.set("cache_dir", cache_dir);
  return settings;
}

struct Bake : test::CachedBake {
  uint64_t refinement_rays = 0;
  uint64_t links = 0;
  std::string cache_path() const { return text_of("meshless_cache_path"); }
};

const PrecomputationCodec& codec() {
  static const MeshlessSolver solver;
  return *solver.codec();
}

// Solves and evaluates at the points, as a bake job does.
Bake bake(const SceneDescription& description, const BakePoints& points, const Settings& settings) {
  const Scene scene = build_scene(description);
  const RayTracer tracer(scene);
  const DirectLight direct(scene, tracer);
  MeshlessSolver solver;
  JobContext context;
  const auto field =
      run_solver(solver, "meshless", SolveInputs{scene, tracer, direct, settings, &points}, context)
          .field;
  Bake result;
  result.values.resize(points.size());
  field->evaluate(points, result.values, context);
  result.report = context.report().to_json();
  result.warnings = context.report().warnings();
  result.refinement_rays = context.report().count("meshless_refinement_rays");
  result.links = context.report().count("meshless_links");
  return result;
}

TEST(MeshlessCache, SecondBakeLoadsTheFileAndGivesTheSameResult) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake first = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(first.says("meshless_cache", "miss")) << first.report;
  const std::string path = first.cache_path();
  ASSERT_FALSE(path.empty());
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(fs::path(path).filename().string().size(),
            std::string("meshless-.bgcache").size() + 16);
  EXPECT_EQ(folder.file_count(), 1u);  // no temporary file left behind
  EXPECT_GT(first.refinement_rays, 0u);
  EXPECT_TRUE(first.warnings.empty());

  const Bake second = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(second.says("meshless_cache", "hit")) << second.report;
  EXPECT_EQ(second.cache_path(), path);
  EXPECT_EQ(second.refinement_rays, 0u);  // nothing was refined
  EXPECT_EQ(second.links, first.links);   // the statistics came with the file
  EXPECT_NE(second.report.find("meshless_cache_load"), std::string::npos);
  EXPECT_TRUE(second.warnings.empty());
  // The same points, operator and statistics: the result is bit for bit the same (the basis'
  // R-trees and DAG are rebuilt from the same points in the same order).
  expect_same_values(first, second);
}

TEST(MeshlessCache, ChangedAlbedoOrMovedVertexMissesWithANewFile) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake base = bake(room(kLight), points, small_settings(folder.path()));
  ASSERT_TRUE(base.says("meshless_cache", "miss"));

  const Bake albedo =
      bake(room(kLight, glm::vec3(0.3f, 0.6f, 0.31f)), points, small_settings(folder.path()));
  EXPECT_TRUE(albedo.says("meshless_cache", "miss")) << albedo.report;
  EXPECT_NE(albedo.cache_path(), base.cache_path());

  SceneDescription moved = room(kLight);
  moved.meshes[1].positions[0] += glm::vec3(0.0f, 0.0f, 0.01f);
  const Bake vertex = bake(moved, points, small_settings(folder.path()));
  EXPECT_TRUE(vertex.says("meshless_cache", "miss")) << vertex.report;
  EXPECT_NE(vertex.cache_path(), base.cache_path());
  EXPECT_NE(vertex.cache_path(), albedo.cache_path());
  EXPECT_EQ(folder.file_count(), 3u);
}

TEST(MeshlessCache, KeyCoversSettingsAndPlacementPointsButNotLightsOrRelightSettings) {
  const SceneDescription scene = room(kLight);
  const BakePoints points = room_points();
  // What the job's cache (solver_run.cpp) leaves out of the key.
  const SettingSchema& schema = method_schema("meshless");
  std::vector<std::string> ignored = schema.keys_with_role(SettingRole::kLighting);
  for (const std::string& key : schema.keys_with_role(SettingRole::kExecution)) {
    ignored.push_back(key);
  }
  // The keys before the settings had a schema, and target_error, irradiance_cache and
  // shadow_cache (settings of the path tracer a method may hand its bake to, like samples).
  std::vector<std::string> sorted = ignored;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted,
            (std::vector<std::string>{"bounces", "cache_dir", "cache_max_mb", "denoise",
                                      "direct_samples", "irradiance_cache", "samples",
                                      "sender_cutoff", "shadow_cache", "target_error", "threads"}));
  std::map<std::string, SettingValue> settings = {{"levels", int64_t(3)}, {"epsilon", 0.01}};
  const CacheKey key =
      precomputation_key(meshless::kPrecomputationCacheVersion, scene, settings, ignored, &points);

  SceneDescription other_light = scene;
  other_light.lights[0].position.x += 0.3f;
  other_light.world_radiance = glm::vec3(0.1f);
  EXPECT_EQ(precomputation_key(meshless::kPrecomputationCacheVersion, other_light, settings,
                               ignored, &points),
            key);
  auto relit = settings;
  relit["direct_samples"] = int64_t(64);
  relit["samples"] = int64_t(5);
  relit["threads"] = int64_t(3);
  relit["cache_dir"] = std::string("/elsewhere");
  EXPECT_EQ(
      precomputation_key(meshless::kPrecomputationCacheVersion, scene, relit, ignored, &points),
      key);

  auto finer = settings;
  finer["epsilon"] = 0.005;
  EXPECT_NE(
      precomputation_key(meshless::kPrecomputationCacheVersion, scene, finer, ignored, &points),
      key);
  auto invisible = settings;  // the gather's visibility test shapes the links
  invisible["visibility"] = int64_t(0);
  EXPECT_NE(
      precomputation_key(meshless::kPrecomputationCacheVersion, scene, invisible, ignored, &points),
      key);
  BakePoints shifted = points;
  shifted.positions[7].x += 1e-4f;
  EXPECT_NE(
      precomputation_key(meshless::kPrecomputationCacheVersion, scene, settings, ignored, &shifted),
      key);
  // With a viewpoint the bake points did not place the basis and are left out.
  EXPECT_NE(
      precomputation_key(meshless::kPrecomputationCacheVersion, scene, settings, ignored, nullptr),
      key);

  // Geometry, materials and every texel shape it (texels are hashed where they lie, apart
  // from the encoding: one changed texel must change the key, the same texels must not).
  const auto key_of = [&](const SceneDescription& changed) {
    return precomputation_key(meshless::kPrecomputationCacheVersion, changed, settings, ignored,
                              &points);
  };
  SceneDescription textured = scene;
  Texture texture;
  texture.width = 2;
  texture.height = 2;
  texture.set_texels(std::vector<glm::vec3>(4, glm::vec3(0.5f)));
  textured.textures.push_back(texture);
  const CacheKey textured_key = key_of(textured);
  EXPECT_NE(textured_key, key);
  SceneDescription same_texels = scene;
  Texture copy;
  copy.width = 2;
  copy.height = 2;
  copy.set_texels(std::vector<glm::vec3>(4, glm::vec3(0.5f)));  // equal, not shared
  same_texels.textures.push_back(copy);
  EXPECT_EQ(key_of(same_texels), textured_key);
  SceneDescription one_texel = scene;
  std::vector<glm::vec3> texels(4, glm::vec3(0.5f));
  texels[3].z = 0.5001f;
  Texture changed;
  changed.width = 2;
  changed.height = 2;
  changed.set_texels(texels);
  one_texel.textures.push_back(changed);
  EXPECT_NE(key_of(one_texel), textured_key);
  SceneDescription darker = scene;
  darker.materials[0].albedo *= 0.9f;
  EXPECT_NE(key_of(darker), key);
}

TEST(MeshlessCache, CorruptOrTruncatedFileIsDetectedAndRebuilt) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake fresh = bake(room(kLight), points, small_settings(folder.path()));
  const std::string path = fresh.cache_path();
  const std::vector<uint8_t> good = read_bytes(path);
  ASSERT_GT(good.size(), 200u);

  // One flipped byte in the payload (S's values are the bulk of it): the checksum catches it.
  std::vector<uint8_t> flipped = good;
  flipped[flipped.size() * 3 / 4] ^= 0x5a;
  write_bytes(path, flipped);
  const Bake after_flip = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(after_flip.says("meshless_cache", "stale")) << after_flip.report;
  EXPECT_TRUE(after_flip.warned("was stale/corrupt")) << after_flip.report;
  EXPECT_GT(after_flip.refinement_rays, 0u);
  expect_same_values(after_flip, fresh);
  // Rebuilt and overwritten (the same size; the bytes differ in the precompute's seconds).
  EXPECT_EQ(read_bytes(path).size(), good.size());

  // Cut short (as a crash during a non-atomic write would leave it).
  write_bytes(path, std::vector<uint8_t>(good.begin(), good.begin() + good.size() / 2));
  const Bake after_cut = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(after_cut.says("meshless_cache", "stale")) << after_cut.report;
  EXPECT_TRUE(after_cut.warned("was stale/corrupt"));
  expect_same_values(after_cut, fresh);

  const Bake again = bake(room(kLight), points, small_settings(folder.path()));
  EXPECT_TRUE(again.says("meshless_cache", "hit")) << again.report;
  expect_same_values(again, fresh);
}

TEST(MeshlessCache, HugeCountsWithAValidChecksumAreRefusedBeforeAllocating) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake fresh = bake(room(kLight), points, small_settings(folder.path()));
  const std::vector<uint8_t> good = read_bytes(fresh.cache_path());
  // Layout (precomputation_cache.h): a 40-byte header, then STAT (16-byte section header and
  // its data), then PNTS whose first u64 is the point count.
  const size_t stat_size_at = 40 + 8;
  uint64_t stat_size = 0;
  for (int i = 0; i < 8; ++i) stat_size |= uint64_t(good[stat_size_at + i]) << (8 * i);
  const size_t count_at = 40 + 16 + stat_size + 16;
  ASSERT_LT(count_at + 8, good.size());

  // A crafted file, not a random corruption: the checksum is recomputed so that only the
  // size checks stand between the count (2^40 points, 32 TiB) and an allocation.
  std::vector<uint8_t> crafted = good;
  for (int i = 0; i < 8; ++i) crafted[count_at + i] = uint8_t((uint64_t(1) << 40) >> (8 * i));
  test::recompute_checksum(crafted);
  const CacheKey key = test::key_of(good);
  EXPECT_NO_THROW(decode_cache_file(codec(), good, key, "good"));
  try {
    decode_cache_file(codec(), crafted, key, "crafted");
    ADD_FAILURE() << "a count beyond the file was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
    EXPECT_NE(std::string(e.what()).find("basis points"), std::string::npos) << e.what();
  }
  // Another key: stale, whatever the content.
  CacheKey other = key;
  other.low ^= 1;
  EXPECT_THROW(decode_cache_file(codec(), good, other, "other"), Error);
}

// Damage that a checksum cannot catch (a forged or miscomputed trailer): any byte changed,
// checksum made valid again, must give either a loaded precomputation or Error(BAD_FILE),
// never a crash, an out-of-range read or a huge allocation (this code runs inside Blender;
// the sanitizer build checks the reads).
TEST(MeshlessCache, ForgedBytesWithAValidChecksumNeverCrash) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const Bake fresh = bake(room(kLight), points, small_settings(folder.path()));
  const std::vector<uint8_t> good = read_bytes(fresh.cache_path());
  const CacheKey key = test::key_of(good);
  std::mt19937_64 random(7);
  int refused = 0;
  constexpr int kTrials = 100;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<uint8_t> forged = good;
    // Half the trials in the first 2 KiB (header, statistics, counts), half anywhere.
    const size_t span = trial % 2 == 0 ? std::min<size_t>(2048, good.size() - 8) : good.size() - 8;
    const size_t at = random() % span;
    forged[at] ^= uint8_t(1 + random() % 255);
    test::recompute_checksum(forged);
    try {
      decode_cache_file(codec(), forged, key, "forged");
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE) << "byte " << at << ": " << e.what();
      ++refused;
    }
  }
  // Most bytes are S's values and point coordinates, which any float may hold, so many
  // forgeries load; but the header and counts are checked, so some must be refused.
  EXPECT_GT(refused, 0);
}

TEST(MeshlessCache, MovedLightHitsAndEqualsAFreshBakeWithTheMovedLight) {
  const CacheFolder folder;
  const BakePoints points = room_points();
  const glm::vec3 moved_light(-0.6f, -0.4f, 1.5f);
  const Bake first = bake(room(kLight), points, small_settings(folder.path()));
  ASSERT_TRUE(first.says("meshless_cache", "miss"));
  const Bake relit = bake(room(moved_light), points, small_settings(folder.path()));
  EXPECT_TRUE(relit.says("meshless_cache", "hit")) << relit.report;
  const Bake fresh = bake(room(moved_light), points, small_settings(""));
  EXPECT_TRUE(fresh.says("meshless_cache", "off"));
  // Placement and links do not depend on the lights, so loading them is exactly a full bake.
  expect_same_values(relit, fresh);
  double total = 0.0;
  for (const glm::vec3& v : relit.values) total += v.x;
  EXPECT_GT(total, 0.0);
  EXPECT_NE(relit.values, first.values);  // the light did move
}

TEST(MeshlessCache, UnwritableFolderWarnsAndStillBakes) {
  const CacheFolder folder;
  fs::create_directories(folder.path());
  // A folder inside a regular file cannot be created, whatever the user's permissions.
  const std::string blocker = folder.path() + "/a_file";
  write_bytes(blocker, {1, 2, 3});
  const BakePoints points = room_points();
  const Bake cached = bake(room(kLight), points, small_settings(blocker + "/cache"));
  EXPECT_TRUE(cached.says("meshless_cache", "miss")) << cached.report;
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
TEST(MeshlessCache, JobsThroughTheCApiSaveAndLoad) {
  const CacheFolder folder;
  const test::ScenePtr scene = test::new_box_scene();
  constexpr size_t kCount = 16;
  const test::PointsPtr points = test::new_floor_points(kCount);
  const test::SettingsPtr settings = test::new_settings();
  ASSERT_EQ(bakegi_settings_set_string(settings.get(), "method", "meshless"), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "levels", 2), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_float(settings.get(), "coarse_spacing", 0.4), BAKEGI_OK);
  ASSERT_EQ(bakegi_settings_set_int(settings.get(), "gather_rays", 16), BAKEGI_OK);
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
  EXPECT_NE(reports[0].find("\"meshless_cache\": \"miss\""), std::string::npos) << reports[0];
  EXPECT_NE(reports[1].find("\"meshless_cache\": \"hit\""), std::string::npos) << reports[1];
  EXPECT_EQ(results[0], results[1]);
  EXPECT_EQ(folder.file_count(), 1u);
}

}  // namespace
}  // namespace bakegi
