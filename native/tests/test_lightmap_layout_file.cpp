// The .bgl lightmap layout file: written and read back through the C API it gives the same
// info, points and (byte for byte) EXR files, and keeps "rejection has run" and the UV
// seams (version 1 files, from before seams, still read); a truncated, bit-flipped,
// foreign or lying file is BAKEGI_ERROR_BAD_FILE naming the problem (a huge count fails
// before anything is allocated for it), a missing one BAKEGI_ERROR_IO.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lightmap/lightmap_layout_file.h"
#include "bakegi/bakegi.h"
#include "bakegi/bakegi_handles.hpp"
#include "lightmap_test_scene.h"
#include "util/byte_stream.h"

namespace bakegi::test {
namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Stores a new checksum, so that a test reaches the checks behind it.
void rehash(std::vector<uint8_t>& bytes) {
  const uint64_t hash = fnv1a64(std::span<const uint8_t>(bytes).first(bytes.size() - 8));
  for (int i = 0; i < 8; ++i) bytes[bytes.size() - 8 + i] = uint8_t(hash >> (8 * i));
}

void put_u32(std::vector<uint8_t>& bytes, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = uint8_t(v >> (8 * i));
}
void put_u64(std::vector<uint8_t>& bytes, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) bytes[at + i] = uint8_t(v >> (8 * i));
}

// Offsets in a file: header (24 bytes), flags, lightmap count, then the first lightmap's
// section header (16) and its width, height, sample count.
constexpr size_t kLightmapCountAt = 28;
constexpr size_t kFirstWidthAt = 32 + 16;
constexpr size_t kFirstSampleCountAt = kFirstWidthAt + 8;

class LightmapLayoutFile : public LightmapFilesTest {
 protected:
  // Two lightmaps: an atlas of a floor and a box lid (added with add_to), and a wall; then
  // rejection (the box sunk into the floor hides some floor texels).
  void SetUp() override {
    LightmapFilesTest::SetUp();
    scene_ = lit_scene();
    const Quad floor({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
    const Quad wall({0, 2, 1}, {2, 0, 0}, {0, 0, 1});
    const Quad lid({0, 0, 0.5f}, {0.5f, 0, 0}, {0, 0.5f, 0});
    const std::vector<Quad> box_sides = {
        Quad({0, 0, -0.25f}, {0, 0.5f, 0}, {0.5f, 0, 0}),
        Quad({0.5f, 0, 0.125f}, {0, 0.5f, 0}, {0, 0, 0.375f}),
        Quad({-0.5f, 0, 0.125f}, {0, 0, 0.375f}, {0, 0.5f, 0}),
        Quad({0, 0.5f, 0.125f}, {0, 0, 0.375f}, {0.5f, 0, 0}),
        Quad({0, -0.5f, 0.125f}, {0.5f, 0, 0}, {0, 0, 0.375f}),
    };
    const uint32_t floor_mesh = floor.add_to(scene_.get(), 1);
    const uint32_t wall_mesh = wall.add_to(scene_.get(), 2);
    const uint32_t lid_mesh = lid.add_to(scene_.get(), 3);
    for (const Quad& q : box_sides) q.add_to(scene_.get(), 4);
    lightmaps_ = new_lightmaps();
    const std::vector<float> floor_uvs = floor.placed_uvs({0.5f, 1.0f}, {0, 0});
    const std::vector<float> lid_uvs = lid.placed_uvs({0.25f, 0.5f}, {0.625f, 0.25f});
    ASSERT_EQ(bakegi_lightmaps_add(lightmaps_.get(), scene_.get(), floor_mesh, floor_uvs.data(), 16,
                                   8, nullptr),
              BAKEGI_OK);
    ASSERT_EQ(bakegi_lightmaps_add_to(lightmaps_.get(), 0, scene_.get(), lid_mesh, lid_uvs.data()),
              BAKEGI_OK)
        << bakegi_last_error();
    ASSERT_EQ(bakegi_lightmaps_add(lightmaps_.get(), scene_.get(), wall_mesh, wall.uvs.data(), 5, 3,
                                   nullptr),
              BAKEGI_OK);
    uint64_t rejected = 0;
    ASSERT_EQ(bakegi_lightmaps_reject_inside(lightmaps_.get(), scene_.get(), 0, 0, 0, &rejected),
              BAKEGI_OK)
        << bakegi_last_error();
    ASSERT_GT(rejected, 0u);  // the round trip must carry rejected texels and counters
    ASSERT_EQ(bakegi_lightmaps_write_file(lightmaps_.get(), path("layout.bgl").c_str()), BAKEGI_OK)
        << bakegi_last_error();
  }

  // Reads `bytes` written to a file; returns the status (and checks failure leaves NULL).
  bakegi_status read_back(const std::vector<uint8_t>& bytes) {
    write_bytes(path("changed.bgl"), bytes);
    bakegi_lightmaps* read = reinterpret_cast<bakegi_lightmaps*>(1);
    const bakegi_status status = bakegi_lightmaps_read_file(path("changed.bgl").c_str(), &read);
    if (status == BAKEGI_OK) {
      bakegi_lightmaps_destroy(read);
    } else {
      EXPECT_EQ(read, nullptr);
    }
    return status;
  }

  std::string last_error() const { return bakegi_last_error(); }

  SceneHandle scene_;
  LightmapsPtr lightmaps_;
};

TEST_F(LightmapLayoutFile, RoundTripGivesTheSamePointsAndExrs) {
  bakegi_lightmaps* raw = nullptr;
  ASSERT_EQ(bakegi_lightmaps_read_file(path("layout.bgl").c_str(), &raw), BAKEGI_OK)
      << bakegi_last_error();
  LightmapsPtr read(raw);
  ASSERT_EQ(bakegi_lightmaps_count(read.get()), 2u);
  for (uint32_t m = 0; m < 2; ++m) {
    bakegi_lightmap_info a{}, b{};
    ASSERT_EQ(bakegi_lightmaps_get_info(lightmaps_.get(), m, &a), BAKEGI_OK);
    ASSERT_EQ(bakegi_lightmaps_get_info(read.get(), m, &b), BAKEGI_OK);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.first_point, b.first_point);
    EXPECT_EQ(a.point_count, b.point_count);
    EXPECT_EQ(a.covered_texels, b.covered_texels);
    EXPECT_EQ(a.rejected_samples, b.rejected_samples);
    EXPECT_EQ(a.skipped_triangles, b.skipped_triangles);
  }

  bakegi_points *raw_a = nullptr, *raw_b = nullptr;
  ASSERT_EQ(bakegi_lightmaps_get_points(lightmaps_.get(), &raw_a), BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_get_points(read.get(), &raw_b), BAKEGI_OK);
  PointsHandle points_a(raw_a), points_b(raw_b);
  const uint64_t count = bakegi_points_count(points_a.get());
  ASSERT_EQ(count, bakegi_points_count(points_b.get()));
  std::vector<float> pa(3 * count), pb(3 * count), na(3 * count), nb(3 * count);
  std::vector<uint32_t> ia(count), ib(count);
  ASSERT_EQ(bakegi_points_get(points_a.get(), pa.data(), na.data(), ia.data()), BAKEGI_OK);
  ASSERT_EQ(bakegi_points_get(points_b.get(), pb.data(), nb.data(), ib.data()), BAKEGI_OK);
  EXPECT_EQ(pa, pb);
  EXPECT_EQ(na, nb);
  EXPECT_EQ(ia, ib);

  // EXRs of both, with a result that differs per point, padding filling the rejected
  // texels: identical files (the weights, texels and coverage came back too).
  std::vector<float> rgb = pa;
  for (float& v : rgb) v = v * v + 0.125f;
  for (uint32_t m = 0; m < 2; ++m) {
    const std::string a = path("a" + std::to_string(m) + ".exr");
    const std::string b = path("b" + std::to_string(m) + ".exr");
    ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps_.get(), m, rgb.data(), count, a.c_str(), 4, 0,
                                         BAKEGI_EXR_ZIP),
              BAKEGI_OK);
    ASSERT_EQ(bakegi_lightmaps_write_exr(read.get(), m, rgb.data(), count, b.c_str(), 4, 0,
                                         BAKEGI_EXR_ZIP),
              BAKEGI_OK);
    const std::vector<uint8_t> bytes_a = file_bytes(a);
    EXPECT_FALSE(bytes_a.empty());
    EXPECT_EQ(bytes_a, file_bytes(b)) << "lightmap " << m;
  }

  // The read lightmaps know rejection has run: adding to them is refused.
  const Quad extra({0, 0, 3}, {0.1f, 0, 0}, {0, 0.1f, 0});
  const uint32_t mesh = extra.add_to(scene_.get(), 9);
  EXPECT_EQ(bakegi_lightmaps_add_to(read.get(), 1, scene_.get(), mesh, extra.uvs.data()),
            BAKEGI_ERROR_INVALID_ARGUMENT);

  // Writing again gives the same bytes (the file holds nothing but the layout), and leaves
  // no temporary file behind.
  ASSERT_EQ(bakegi_lightmaps_write_file(read.get(), path("again.bgl").c_str()), BAKEGI_OK);
  EXPECT_EQ(file_bytes(path("again.bgl")), file_bytes(path("layout.bgl")));
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(directory_)) ++files;
  EXPECT_EQ(files, 6u);  // layout.bgl, again.bgl and the four .exr files
}

// What `bakegi bake scene.bgs --lightmaps layout.bgl --exr-dir DIR` does, through the C API:
// the scene file with the layout's points and the layout file, both read back, bake to the
// same EXR files (byte for byte) as the lightmaps that never left memory.
TEST_F(LightmapLayoutFile, SceneFileAndLayoutBakeTheSameExrsAsInMemory) {
  bakegi_points* raw_points = nullptr;
  ASSERT_EQ(bakegi_lightmaps_get_points(lightmaps_.get(), &raw_points), BAKEGI_OK);
  const PointsHandle points(raw_points);
  ASSERT_EQ(bakegi_file_write(path("scene.bgs").c_str(), scene_.get(), points.get()), BAKEGI_OK)
      << bakegi_last_error();

  bakegi_scene* raw_scene = nullptr;
  bakegi_points* raw_file_points = nullptr;
  ASSERT_EQ(bakegi_file_read(path("scene.bgs").c_str(), &raw_scene, &raw_file_points), BAKEGI_OK);
  const SceneHandle file_scene(raw_scene);
  const PointsHandle file_points(raw_file_points);
  bakegi_lightmaps* raw_layout = nullptr;
  ASSERT_EQ(bakegi_lightmaps_read_file(path("layout.bgl").c_str(), &raw_layout), BAKEGI_OK);
  const LightmapsPtr layout(raw_layout);

  // Direct light only: deterministic and fast; the point light shadows the floor by the box.
  auto bake = [](const bakegi_scene* scene, const bakegi_points* points) {
    bakegi_settings* raw_settings = nullptr;
    EXPECT_EQ(bakegi_settings_create(&raw_settings), BAKEGI_OK);
    const SettingsHandle settings(raw_settings);
    EXPECT_EQ(bakegi_settings_set_string(settings.get(), "method", "direct"), BAKEGI_OK)
        << bakegi_last_error();
    bakegi_job* raw_job = nullptr;
    EXPECT_EQ(bakegi_job_start(scene, points, settings.get(), &raw_job), BAKEGI_OK)
        << bakegi_last_error();
    const JobHandle job(raw_job);
    EXPECT_EQ(bakegi_job_wait(job.get()), BAKEGI_OK) << bakegi_last_error();
    const uint64_t count = bakegi_points_count(points);
    std::vector<float> rgb(3 * count);
    EXPECT_EQ(bakegi_job_get_result(job.get(), rgb.data(), count), BAKEGI_OK);
    return rgb;
  };
  const uint64_t count = bakegi_points_count(points.get());
  ASSERT_EQ(bakegi_points_count(file_points.get()), count);
  const std::vector<float> in_memory = bake(scene_.get(), points.get());
  const std::vector<float> from_files = bake(file_scene.get(), file_points.get());
  ASSERT_EQ(in_memory, from_files);
  float brightest = 0;
  for (float v : in_memory) brightest = std::max(brightest, v);
  EXPECT_GT(brightest, 0.0f);  // a lit bake, not zeros compared with zeros

  for (uint32_t m = 0; m < 2; ++m) {
    const std::string a = path("memory" + std::to_string(m) + ".exr");
    const std::string b = path("files" + std::to_string(m) + ".exr");
    ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps_.get(), m, in_memory.data(), count, a.c_str(), 4,
                                         0, BAKEGI_EXR_ZIP),
              BAKEGI_OK);
    ASSERT_EQ(bakegi_lightmaps_write_exr(layout.get(), m, from_files.data(), count, b.c_str(), 4, 0,
                                         BAKEGI_EXR_ZIP),
              BAKEGI_OK);
    EXPECT_EQ(file_bytes(a), file_bytes(b)) << "lightmap " << m;
  }
}

TEST_F(LightmapLayoutFile, DamagedFilesAreBadFiles) {
  const std::vector<uint8_t> good = file_bytes(path("layout.bgl"));
  ASSERT_GT(good.size(), 100u);
  EXPECT_EQ(read_back(good), BAKEGI_OK) << last_error();

  std::vector<uint8_t> truncated(good.begin(), good.end() - 13);
  EXPECT_EQ(read_back(truncated), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("truncated"), std::string::npos) << last_error();
  EXPECT_NE(last_error().find("changed.bgl"), std::string::npos) << last_error();
  EXPECT_EQ(read_back(std::vector<uint8_t>(good.begin(), good.begin() + 20)),
            BAKEGI_ERROR_BAD_FILE);

  std::vector<uint8_t> flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_EQ(read_back(flipped), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("checksum"), std::string::npos) << last_error();

  std::vector<uint8_t> magic = good;
  magic[7] = 'S';  // a scene file's magic
  rehash(magic);
  EXPECT_EQ(read_back(magic), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("not a bakegi lightmap layout file"), std::string::npos)
      << last_error();

  std::vector<uint8_t> version = good;
  put_u32(version, 8, 99);
  rehash(version);
  EXPECT_EQ(read_back(version), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("version 99"), std::string::npos) << last_error();
}

// Counts that promise more than the file holds fail before anything is allocated for them:
// were they allocated, 2^60 samples or 2^32 lightmaps would fail as OUT_OF_MEMORY (or
// abort under ASan), not as BAD_FILE.
TEST_F(LightmapLayoutFile, CountsLargerThanTheFileFailBeforeAllocating) {
  const std::vector<uint8_t> good = file_bytes(path("layout.bgl"));
  std::vector<uint8_t> samples = good;
  put_u64(samples, kFirstSampleCountAt, uint64_t(1) << 60);
  rehash(samples);
  EXPECT_EQ(read_back(samples), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("lightmap samples"), std::string::npos) << last_error();

  std::vector<uint8_t> lightmaps = good;
  put_u32(lightmaps, kLightmapCountAt, 0xffffffffu);
  rehash(lightmaps);
  EXPECT_EQ(read_back(lightmaps), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("lightmaps needs"), std::string::npos) << last_error();

  // The largest map the format allows: its coverage alone needs 8 MiB the file lacks.
  std::vector<uint8_t> size = good;
  put_u32(size, kFirstWidthAt, 8192);
  put_u32(size, kFirstWidthAt + 4, 8192);
  rehash(size);
  EXPECT_EQ(read_back(size), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("texel coverage"), std::string::npos) << last_error();

  std::vector<uint8_t> too_wide = good;
  put_u32(too_wide, kFirstWidthAt, 8193);
  rehash(too_wide);
  EXPECT_EQ(read_back(too_wide), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("8193 x 8"), std::string::npos) << last_error();
}

// A well-formed file whose contents the rasterizer could not have made.
TEST_F(LightmapLayoutFile, ContentsAreChecked) {
  LightmapLayout layout;
  layout.lightmaps.resize(1);
  TexelSamples& s = layout.lightmaps[0].samples;
  s.width = 2;
  s.height = 2;
  s.points.positions = {{0, 0, 0}};
  s.points.normals = {{0, 0, 1}};
  s.points.object_ids = {5};
  s.face_normals = {{0, 0, 1}};
  s.texel = {3};
  s.weight = {0.5f};
  s.covered = {0, 0, 0, 1};
  const std::string name = "layout in memory";
  EXPECT_NO_THROW(decode_lightmap_layout(encode_lightmap_layout(layout), name));

  auto refused = [&](LightmapLayout changed, const std::string& expected) {
    try {
      decode_lightmap_layout(encode_lightmap_layout(changed), name);
      ADD_FAILURE() << "accepted; expected " << expected;
    } catch (const Error& e) {
      EXPECT_EQ(e.status(), BAKEGI_ERROR_BAD_FILE);
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  LightmapLayout bad = layout;
  bad.lightmaps[0].samples.texel = {4};
  refused(bad, "texel 4 is outside");
  bad = layout;
  bad.lightmaps[0].samples.covered = {1, 0, 0, 1};
  refused(bad, "coverage does not match");
  bad = layout;
  bad.lightmaps[0].samples.weight = {0.0f};
  refused(bad, "weight");
  bad = layout;
  bad.lightmaps[0].samples.points.normals = {{0, 0, 2}};
  refused(bad, "not unit length");
  bad = layout;
  bad.lightmaps[0].samples.points.positions = {{NAN, 0, 0}};
  refused(bad, "position is not finite");
  bad = layout;
  bad.lightmaps[0].seams = {LightmapSeam{{{0, 0}, {0, 1}}, {{1, 0}, {1, INFINITY}}}};
  refused(bad, "seam 0: a UV is not finite");
}

// One lightmap with `seams` seams, as encode_lightmap_layout writes it.
LightmapLayout one_texel_layout(size_t seams) {
  LightmapLayout layout;
  layout.lightmaps.resize(1);
  TexelSamples& s = layout.lightmaps[0].samples;
  s.width = 2;
  s.height = 1;
  s.points.positions = {{0, 0, 0}};
  s.points.normals = {{0, 0, 1}};
  s.points.object_ids = {5};
  s.face_normals = {{0, 0, 1}};
  s.texel = {1};
  s.weight = {1.0f};
  s.covered = {0, 1};
  for (size_t i = 0; i < seams; ++i) {
    const float u = 0.1f * float(i);
    layout.lightmaps[0].seams.push_back({{{u, 0}, {u, 1}}, {{u + 0.5f, 0.25f}, {u + 0.5f, 0.75f}}});
  }
  return layout;
}

bool same_seams(const std::vector<LightmapSeam>& a, const std::vector<LightmapSeam>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      if (a[i].a[k] != b[i].a[k] || a[i].b[k] != b[i].b[k]) return false;
    }
  }
  return true;
}

TEST_F(LightmapLayoutFile, SeamsSurviveTheRoundTrip) {
  const LightmapLayout layout = one_texel_layout(3);
  const LightmapLayout read = decode_lightmap_layout(encode_lightmap_layout(layout), "seams");
  ASSERT_EQ(read.lightmaps.size(), 1u);
  EXPECT_TRUE(same_seams(read.lightmaps[0].seams, layout.lightmaps[0].seams));

  // Through the C API: a mesh of two charts has a seam, stitched into its EXR; the layout
  // read back writes the same bytes (it would not, unstitched).
  const Strip strip;
  const uint32_t mesh = strip.add_to(scene_.get(), 7);
  const LightmapsPtr lightmaps = new_lightmaps();
  const std::vector<float> uvs = strip.uvs({0.1f, 0.1f}, 0.3f, {0.55f, 0.2f}, 0.35f);
  ASSERT_EQ(bakegi_lightmaps_add(lightmaps.get(), scene_.get(), mesh, uvs.data(), 24, 24, nullptr),
            BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_write_file(lightmaps.get(), path("strip.bgl").c_str()), BAKEGI_OK);
  const LightmapLayout strip_layout = read_lightmap_layout_file(path("strip.bgl"));
  ASSERT_EQ(strip_layout.lightmaps.size(), 1u);
  EXPECT_EQ(strip_layout.lightmaps[0].seams.size(), 1u);
  bakegi_lightmaps* raw = nullptr;
  ASSERT_EQ(bakegi_lightmaps_read_file(path("strip.bgl").c_str(), &raw), BAKEGI_OK);
  const LightmapsPtr strip_read(raw);
  bakegi_points* raw_points = nullptr;
  ASSERT_EQ(bakegi_lightmaps_get_points(lightmaps.get(), &raw_points), BAKEGI_OK);
  const PointsHandle points(raw_points);
  const uint64_t count = bakegi_points_count(points.get());
  std::vector<float> rgb(3 * count);
  ASSERT_EQ(bakegi_points_get(points.get(), rgb.data(), nullptr, nullptr), BAKEGI_OK);
  for (float& v : rgb) v = 0.25f + 0.5f * v;  // a gradient across the seam
  ASSERT_EQ(bakegi_lightmaps_write_exr(lightmaps.get(), 0, rgb.data(), count,
                                       path("memory.exr").c_str(), 2, 1, BAKEGI_EXR_ZIP),
            BAKEGI_OK);
  ASSERT_EQ(bakegi_lightmaps_write_exr(strip_read.get(), 0, rgb.data(), count,
                                       path("file.exr").c_str(), 2, 1, BAKEGI_EXR_ZIP),
            BAKEGI_OK);
  EXPECT_EQ(file_bytes(path("memory.exr")), file_bytes(path("file.exr")));

  // A seam count larger than the file fails before anything is allocated for it: the
  // count sits before the last seam's 32 bytes and the trailer.
  std::vector<uint8_t> bytes = encode_lightmap_layout(one_texel_layout(1));
  put_u64(bytes, bytes.size() - 8 - 32 - 8, uint64_t(1) << 60);
  rehash(bytes);
  EXPECT_EQ(read_back(bytes), BAKEGI_ERROR_BAD_FILE);
  EXPECT_NE(last_error().find("seams needs"), std::string::npos) << last_error();
}

// Files of version 1 (written before seams were stored) read as lightmaps without seams.
TEST_F(LightmapLayoutFile, VersionOneReadsWithoutSeams) {
  const LightmapLayout layout = one_texel_layout(0);
  std::vector<uint8_t> bytes = encode_lightmap_layout(layout);
  // Version 1 is version 2 without the seam count (u64, 0 here) that ends each lightmap
  // section: drop it from the one section and from the sizes in the header (at 16) and
  // the section header (at 32 + 8).
  const size_t seam_count_at = bytes.size() - 8 - 8;
  bytes.erase(bytes.begin() + seam_count_at, bytes.begin() + seam_count_at + 8);
  put_u32(bytes, 8, 1);
  uint64_t payload = 0, section = 0;
  for (int i = 0; i < 8; ++i) {
    payload |= uint64_t(bytes[16 + i]) << (8 * i);
    section |= uint64_t(bytes[40 + i]) << (8 * i);
  }
  put_u64(bytes, 16, payload - 8);
  put_u64(bytes, 40, section - 8);
  rehash(bytes);
  const LightmapLayout read = decode_lightmap_layout(bytes, "version 1");
  ASSERT_EQ(read.lightmaps.size(), 1u);
  EXPECT_TRUE(read.lightmaps[0].seams.empty());
  EXPECT_EQ(read.lightmaps[0].samples.texel, layout.lightmaps[0].samples.texel);
  EXPECT_EQ(read.lightmaps[0].samples.covered, layout.lightmaps[0].samples.covered);
  EXPECT_EQ(read_back(bytes), BAKEGI_OK) << last_error();

  // The same bytes claiming version 2 lack the seam count.
  put_u32(bytes, 8, 2);
  rehash(bytes);
  EXPECT_EQ(read_back(bytes), BAKEGI_ERROR_BAD_FILE);
}

TEST_F(LightmapLayoutFile, MissingFileIsIoAndArgumentsAreChecked) {
  bakegi_lightmaps* read = reinterpret_cast<bakegi_lightmaps*>(1);
  const std::string missing = path("missing.bgl");
  EXPECT_EQ(bakegi_lightmaps_read_file(missing.c_str(), &read), BAKEGI_ERROR_IO);
  EXPECT_EQ(read, nullptr);
  EXPECT_NE(last_error().find(missing), std::string::npos) << last_error();
  EXPECT_EQ(bakegi_lightmaps_read_file(nullptr, &read), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_read_file("", &read), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_read_file(missing.c_str(), nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);

  EXPECT_EQ(bakegi_lightmaps_write_file(nullptr, missing.c_str()), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_file(lightmaps_.get(), nullptr), BAKEGI_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(bakegi_lightmaps_write_file(lightmaps_.get(), ""), BAKEGI_ERROR_INVALID_ARGUMENT);
  const std::string unwritable = path("no/such/folder/layout.bgl");
  EXPECT_EQ(bakegi_lightmaps_write_file(lightmaps_.get(), unwritable.c_str()), BAKEGI_ERROR_IO);
  EXPECT_NE(last_error().find("no/such/folder"), std::string::npos) << last_error();
}

}  // namespace
}  // namespace bakegi::test
