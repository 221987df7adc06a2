#include "bake/precomputation_store.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <utility>

#include <tbb/parallel_for.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <new>

#include "bakegi/bakegi.h"
#include "scene/scene_file.h"
#include "solvers/solver.h"
#include "util/byte_stream.h"
#include "util/error.h"
#include "util/file_bytes.h"
#include "util/job_context.h"
#include "util/random.h"

namespace bakegi {

namespace {

constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8 + 8;
constexpr size_t kTrailerBytes = 8;

std::array<uint8_t, 8> magic_of(const PrecomputationCodec& codec) {
  return {'B', 'A', 'K', 'E', 'G', 'I', '\0', uint8_t(codec.magic())};
}

// One 64-bit hash of `bytes` seeded by `seed`: SplitMix64's bijective mix chained over
// little-endian 8-byte words.
uint64_t word_hash(std::span<const uint8_t> bytes, uint64_t seed) {
  uint64_t hash = mix64(bytes.size() ^ seed);
  size_t at = 0;
  for (; at + 8 <= bytes.size(); at += 8) {
    uint64_t word = 0;
    std::memcpy(&word, bytes.data() + at, 8);
    if constexpr (std::endian::native == std::endian::big) word = __builtin_bswap64(word);
    hash = mix64(hash ^ word);
  }
  uint64_t tail = 0;
  for (int i = 0; at < bytes.size(); ++at, ++i) tail |= uint64_t(bytes[at]) << (8 * i);
  return mix64(hash ^ tail);
}

// A 128-bit hash of a large block (a scene's meshes and textures, hundreds of MB on Sponza):
// two differently seeded word hashes of every 4 MiB chunk, in parallel, chained in chunk
// order. The byte-serial FNV-1a and the scene file's own checksum it replaced took 2.2 s of
// every Sponza bake.
std::pair<uint64_t, uint64_t> block_hash(std::span<const uint8_t> bytes) {
  constexpr size_t kChunk = size_t(4) << 20;
  constexpr uint64_t kSeedHigh = 0x6261'6b65'6769'0001ull, kSeedLow = 0x6261'6b65'6769'0002ull;
  const size_t chunks = (bytes.size() + kChunk - 1) / kChunk;
  std::vector<std::pair<uint64_t, uint64_t>> hashes(chunks);
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    const std::span<const uint8_t> chunk =
        bytes.subspan(c * kChunk, std::min(kChunk, bytes.size() - c * kChunk));
    hashes[c] = {word_hash(chunk, kSeedHigh), word_hash(chunk, kSeedLow)};
  });
  uint64_t high = mix64(bytes.size() ^ kSeedHigh), low = mix64(bytes.size() ^ kSeedLow);
  for (const auto& [h, l] : hashes) {
    high = mix64(high ^ h);
    low = mix64(low ^ l);
  }
  return {high, low};
}

void add_hash(ByteWriter& w, std::span<const uint8_t> bytes) {
  const auto [high, low] = block_hash(bytes);
  w.u64(bytes.size());
  w.u64(high);
  w.u64(low);
}

// The textures, materials and meshes sections of the scene's .bgs sections (scene_file.h:
// TEXR, MATL, MESH, LGHT, WRLD), leaving out lights and world.
std::span<const uint8_t> geometry_and_materials(std::span<const uint8_t> encoded) {
  constexpr size_t kSceneHeaderBytes = 0, kSectionHeaderBytes = 16;
  size_t at = kSceneHeaderBytes;
  for (uint32_t tag : {section_tag("TEXR"), section_tag("MATL"), section_tag("MESH")}) {
    ByteReader r(encoded.subspan(std::min(at, encoded.size())), "scene encoding");
    if (r.u32() != tag) {
      throw Error(BAKEGI_ERROR_INTERNAL, "precomputation cache: the scene file layout changed");
    }
    r.u32();
    const uint64_t size = r.u64();
    r.need(size, 1, "section");
    at += kSectionHeaderBytes + size;
  }
  return encoded.subspan(kSceneHeaderBytes, at - kSceneHeaderBytes);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::string CacheKey::file_name(const std::string& codec_name) const {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(high));
  return codec_name + "-" + hex + ".bgcache";
}

CacheKey precomputation_key(uint32_t codec_version, const SceneDescription& scene,
                            const std::map<std::string, SettingValue>& used_settings,
                            const std::vector<std::string>& ignored_settings,
                            const BakePoints* placement_points) {
  ByteWriter w;
  w.u32(codec_version);
  w.u32(BAKEGI_VERSION_MAJOR);
  w.u32(BAKEGI_VERSION_MINOR);
  w.u32(BAKEGI_VERSION_PATCH);
  w.u32(kSceneFileVersion);
  {
    // Hashed at once so that the key material stays small for large scenes. The texels
    // (300 MB on Sponza) are hashed where they lie instead of being copied into the
    // encoding first: the encoding gets each texture's size only.
    SceneDescription shapes;
    shapes.materials = scene.materials;
    shapes.meshes = scene.meshes;  // shared, not copied
    for (const Texture& texture : scene.textures) {
      Texture size_only;
      size_only.width = texture.width;
      size_only.height = texture.height;
      shapes.textures.push_back(size_only);
    }
    const std::vector<uint8_t> encoded = encode_scene_sections(shapes);
    add_hash(w, geometry_and_materials(encoded));
    for (const Texture& texture : scene.textures) {
      // The texels as held (texel_palette.h), without a copy of them as floats.
      if (const TexelPalette* palette = texture.palette()) {
        add_hash(w,
                 std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(palette->values.data()),
                                          sizeof(palette->values)));
        add_hash(w, palette->indices);
      } else {
        add_hash(w,
                 std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(texture.float_texels()),
                                          texture.texel_count() * sizeof(glm::vec3)));
      }
    }
  }
  for (const auto& [key, value] : used_settings) {
    if (std::find(ignored_settings.begin(), ignored_settings.end(), key) !=
        ignored_settings.end()) {
      continue;
    }
    w.string(key);
    w.u32(uint32_t(value.index()));
    if (const int64_t* i = std::get_if<int64_t>(&value)) w.u64(uint64_t(*i));
    if (const double* d = std::get_if<double>(&value)) w.f64(*d);
    if (const std::string* text = std::get_if<std::string>(&value)) w.string(*text);
  }
  w.u32(placement_points ? 1 : 0);
  if (placement_points) {
    ByteWriter points;
    points.u64(placement_points->size());
    for (const glm::vec3& p : placement_points->positions) points.vec3(p);
    for (const glm::vec3& n : placement_points->normals) points.vec3(n);
    for (uint32_t id : placement_points->object_ids) points.u32(id);
    add_hash(w, points.bytes);
  }
  const auto [high, low] = block_hash(w.bytes);
  return CacheKey{high, low};
}

std::vector<uint8_t> encode_cache_file(const PrecomputationCodec& codec,
                                       const Precomputation& precomputation, const CacheKey& key) {
  ByteWriter w;
  const std::array<uint8_t, 8> magic = magic_of(codec);
  w.bytes.insert(w.bytes.end(), magic.begin(), magic.end());
  w.u32(codec.version());
  w.u32(0);
  w.u64(key.high);
  w.u64(key.low);
  const size_t payload_size_at = w.bytes.size();
  w.u64(0);  // payload size, patched below
  codec.encode(precomputation, w);
  w.patch_u64(payload_size_at, w.bytes.size() - kHeaderBytes);
  w.u64(fnv1a64(w.bytes));
  return std::move(w.bytes);
}

std::shared_ptr<const Precomputation> decode_cache_file(const PrecomputationCodec& codec,
                                                        std::span<const uint8_t> bytes,
                                                        const CacheKey& expected,
                                                        const std::string& name,
                                                        const JobContext* job) {
  const auto fail = [&](const std::string& what) {
    throw Error(BAKEGI_ERROR_BAD_FILE, name + ": " + what);
  };
  const std::array<uint8_t, 8> magic = magic_of(codec);
  if (bytes.size() < kHeaderBytes + kTrailerBytes ||
      !std::equal(magic.begin(), magic.end(), bytes.begin())) {
    fail("corrupt: not a " + codec.name() + " cache file");
  }
  ByteReader header(bytes.subspan(magic.size(), kHeaderBytes - magic.size()), name);
  const uint32_t version = header.u32();
  if (version != codec.version()) {
    fail("stale: format version " + std::to_string(version) + ", this build uses " +
         std::to_string(codec.version()));
  }
  header.u32();
  CacheKey key;
  key.high = header.u64();
  key.low = header.u64();
  if (!(key == expected)) fail("stale: made for another scene or other settings");
  const uint64_t payload_bytes = header.u64();
  if (payload_bytes != bytes.size() - kHeaderBytes - kTrailerBytes) {
    fail("corrupt: truncated or extended (the header says " + std::to_string(payload_bytes) +
         " payload bytes, the file holds " +
         std::to_string(bytes.size() - kHeaderBytes - kTrailerBytes) + ")");
  }
  const size_t hashed = bytes.size() - kTrailerBytes;
  ByteReader trailer(bytes.subspan(hashed), name);
  if (trailer.u64() != fnv1a64(bytes.first(hashed))) fail("corrupt: checksum mismatch");

  ByteReader payload(bytes.subspan(kHeaderBytes, payload_bytes), name);
  std::shared_ptr<const Precomputation> precomputation = codec.decode(payload, job);
  if (payload.left() != 0) fail("corrupt: unexpected bytes after the last section");
  return precomputation;
}

SettingSpec cache_size_setting() {
  return integer_setting("cache_max_mb", 4096, 0, int64_t(1) << 30, SettingRole::kExecution,
                         "size cap of the cache folder in MB: after a save, the least recently "
                         "used cache files (*.bgcache) beyond it are deleted (report "
                         "\"<method>_cache_evicted\"); 0: no cap");
}

size_t evict_least_recently_used(const std::string& folder, uint64_t max_bytes,
                                 const std::string& keep) {
  namespace fs = std::filesystem;
  if (max_bytes == 0) return 0;
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    uint64_t bytes;
  };
  std::vector<Entry> entries;
  uint64_t total = 0;
  std::error_code error;
  const fs::path kept = utf8_path(keep);
  for (fs::directory_iterator it(utf8_path(folder), error), end; !error && it != end;
       it.increment(error)) {
    std::error_code entry_error;
    if (it->path().extension() != ".bgcache" || !it->is_regular_file(entry_error)) continue;
    const uint64_t bytes = it->file_size(entry_error);
    const fs::file_time_type used = it->last_write_time(entry_error);
    if (entry_error) continue;
    total += bytes;
    if (it->path() != kept) entries.push_back({it->path(), used, bytes});
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.used < b.used; });
  size_t deleted = 0;
  for (const Entry& entry : entries) {
    if (total <= max_bytes) break;
    std::error_code remove_error;
    if (fs::remove(entry.path, remove_error)) ++deleted;
    total -= entry.bytes;  // gone, by us or by another process
  }
  return deleted;
}

std::shared_ptr<const Precomputation> load_or_precompute(
    const CacheRequest& request, JobContext& context,
    const std::function<std::shared_ptr<const Precomputation>()>& make) {
  namespace fs = std::filesystem;
  const PrecomputationCodec& codec = request.codec;
  const std::string prefix = codec.name() + "_cache";
  Report& report = context.report();
  auto start = std::chrono::steady_clock::now();
  const CacheKey key =
      precomputation_key(codec.version(), request.scene, request.settings.used_values(),
                         request.ignored_settings, request.points);
  const fs::path folder = utf8_path(request.folder);
  const fs::path path = folder / key.file_name(codec.name());
  const std::string path_text = utf8_text(path);
  report.add_seconds(prefix + "_key", seconds_since(start));
  report.set_text(prefix + "_path", path_text);

  std::string state = "miss";
  std::error_code exists_error;
  if (fs::exists(path, exists_error)) {
    start = std::chrono::steady_clock::now();
    context.set_stage(codec.name() + ": loading the cached precomputation", 0.02, 0.95);
    try {
      const std::vector<uint8_t> bytes = read_file_bytes(path, request.max_file_bytes);
      std::shared_ptr<const Precomputation> loaded =
          decode_cache_file(codec, bytes, key, utf8_text(path.filename()), &context);
      report.set_text(prefix, "hit");
      // Used now: the least-recently-used eviction reads the modification time.
      std::error_code touch_error;
      fs::last_write_time(path, fs::file_time_type::clock::now(), touch_error);
      report.add_seconds(prefix + "_load", seconds_since(start));
      report.add_count(prefix + "_bytes", bytes.size());
      codec.report_loaded(*loaded, report);
      return loaded;
    } catch (const Error& e) {
      if (e.status() == BAKEGI_ERROR_CANCELLED) throw;
      state = "stale";
      report.warn(codec.name() + " cache " + path_text + " was stale/corrupt (" + e.what() +
                  "): rebuilt");
    } catch (const std::bad_alloc&) {
      state = "stale";
      report.warn(codec.name() + " cache " + path_text +
                  " was stale/corrupt (too large to load): rebuilt");
    }
  }

  std::shared_ptr<const Precomputation> made = make();
  report.set_text(prefix, state);
  // Saving is a convenience: whatever goes wrong is a warning, never a failed bake.
  start = std::chrono::steady_clock::now();
  const std::string not_saved = codec.name() + " cache: the precomputation was not saved: ";
  try {
    std::error_code error;
    fs::create_directories(folder, error);
    if (error) {
      throw Error(BAKEGI_ERROR_IO,
                  "cannot create the folder " + utf8_text(folder) + ": " + error.message());
    }
    const std::vector<uint8_t> bytes = encode_cache_file(codec, *made, key);
    write_file_atomically(path, bytes);
    report.add_count(prefix + "_evicted", evict_least_recently_used(
                                              request.folder, request.max_folder_bytes, path_text));
    report.add_seconds(prefix + "_save", seconds_since(start));
    report.add_count(prefix + "_bytes", bytes.size());
  } catch (const Error& e) {
    report.warn(not_saved + e.what());
  } catch (const std::exception& e) {
    report.warn(not_saved + e.what());
  }
  return made;
}

}  // namespace bakegi
