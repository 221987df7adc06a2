#include "solvers/meshless/precomputation_cache.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>

#include "util/byte_stream.h"
#include "util/error.h"
#include "util/random.h"

namespace bakegi::meshless {

namespace {

constexpr uint32_t kStatistics = section_tag("STAT"), kPoints = section_tag("PNTS"),
                   kTransfer = section_tag("XFER"), kSkyVisibility = section_tag("SKYV"),
                   kReceiverRelations = section_tag("RREL");
constexpr size_t kPointBytes = 3 * 4 + 3 * 4 + 4 + 4;

// The serializers below write every member; a member added to these types must be added
// here too (and kPrecomputationCacheVersion bumped), or the cache would drop it silently.
static_assert(sizeof(BasisPoint) == kPointBytes,
              "BasisPoint changed: update precomputation_cache.cpp and bump the cache version");
static_assert(sizeof(DirectToIndirect) == sizeof(std::array<SparseOperator, 3>),
              "DirectToIndirect changed: update precomputation_cache.cpp and bump the version");

void write_u64s(ByteWriter& w, const std::vector<uint64_t>& values) {
  w.u64(values.size());
  for (uint64_t v : values) w.u64(v);
}

void write_statistics(ByteWriter& w, const MeshlessStatistics& s) {
  const size_t at = w.begin_section(kStatistics);
  w.u32(s.sender_levels);
  write_u64s(w, s.receivers_per_level);
  write_u64s(w, s.links_per_level);
  w.u64(s.links);
  w.u64(s.potential_links);
  w.u32(uint32_t(s.refinement_stopped_at_level));
  w.u32(s.levels_reduced ? 1u : 0u);
  w.u32(s.bounces);
  w.u64(s.bounce_fractions.size());
  for (double f : s.bounce_fractions) w.f64(f);
  w.f64(s.coarse_spacing);
  w.f64(s.mean_free_path);
  w.u64(s.link_bytes);
  w.u64(s.placement_rays);
  w.u64(s.refinement_rays);
  w.f64(s.precompute_seconds);
  w.end_section(at);
}

void write_points(ByteWriter& w, const BasisHierarchy& all) {
  const size_t at = w.begin_section(kPoints);
  w.u64(all.size());
  for (const BasisPoint& p : all.points()) {
    w.vec3(p.position);
    w.vec3(p.normal);
    w.f32(p.radius);
    w.u32(p.level);
  }
  w.end_section(at);
}

void write_transfer(ByteWriter& w, const DirectToIndirect& transfer) {
  const size_t at = w.begin_section(kTransfer);
  for (const SparseOperator& channel : transfer.channel) {
    SparseOperator compressed;
    const SparseOperator* m = &channel;
    if (!channel.isCompressed()) {
      compressed = channel;
      compressed.makeCompressed();
      m = &compressed;
    }
    const int32_t columns = m->cols();
    const int64_t nonzeros = m->nonZeros();
    w.u32(uint32_t(m->rows()));
    w.u32(uint32_t(columns));
    w.u64(uint64_t(nonzeros));
    for (int32_t j = 0; j <= columns; ++j) w.u32(uint32_t(m->outerIndexPtr()[j]));
    for (int64_t k = 0; k < nonzeros; ++k) w.u32(uint32_t(m->innerIndexPtr()[k]));
    for (int64_t k = 0; k < nonzeros; ++k) w.f32(m->valuePtr()[k]);
  }
  w.end_section(at);
}

void write_sky_visibility(ByteWriter& w, const std::vector<float>& visibility) {
  const size_t at = w.begin_section(kSkyVisibility);
  w.u64(visibility.size());
  for (float v : visibility) w.f32(v);
  w.end_section(at);
}

std::vector<float> read_sky_visibility(ByteReader& r, size_t expected) {
  std::vector<float> visibility;
  r.array(visibility, r.u64(), 4, "sky visibility", [&] { return r.f32(); });
  if (visibility.size() != expected) {
    r.fail("corrupt: sky visibility for " + std::to_string(visibility.size()) + " of " +
           std::to_string(expected) + " senders");
  }
  for (float v : visibility) {
    if (!(v >= 0.0f && v <= 1.0f)) r.fail("corrupt: sky visibility outside [0, 1]");
  }
  return visibility;
}

// The receivers' coarser relations (level_completion.h): a point count (0: none kept), the
// row offsets, then (index, weight) per entry.
void write_receiver_relations(ByteWriter& w, const VisibleRelations* relations) {
  const size_t at = w.begin_section(kReceiverRelations);
  const size_t rows = relations ? relations->coarser_offsets.size() - 1 : 0;
  w.u64(rows);
  if (rows > 0) {
    for (uint64_t offset : relations->coarser_offsets) w.u64(offset);
    for (const BasisValue& v : relations->coarser) {
      w.u32(v.index);
      w.f32(v.value);
    }
  }
  w.end_section(at);
}

// Null when the file kept none. Every entry must name a point of a coarser level than its row's.
std::shared_ptr<const VisibleRelations> read_receiver_relations(ByteReader& r,
                                                                const BasisHierarchy& all) {
  const uint64_t rows = r.u64();
  if (rows == 0) return nullptr;
  if (rows != all.size()) {
    r.fail("corrupt: receiver relations for " + std::to_string(rows) + " of " +
           std::to_string(all.size()) + " points");
  }
  auto relations = std::make_shared<VisibleRelations>();
  r.array(relations->coarser_offsets, rows + 1, 8, "receiver relation offsets",
          [&] { return r.u64(); });
  if (relations->coarser_offsets.front() != 0) r.fail("corrupt: receiver relation offsets");
  for (size_t i = 0; i < rows; ++i) {
    if (relations->coarser_offsets[i + 1] < relations->coarser_offsets[i]) {
      r.fail("corrupt: receiver relation offsets decrease");
    }
  }
  r.array(relations->coarser, relations->coarser_offsets.back(), 8, "receiver relations", [&] {
    BasisValue v;
    v.index = r.u32();
    v.value = r.f32();
    return v;
  });
  for (uint32_t j = 0; j < rows; ++j) {
    for (const BasisValue& v : relations->coarser_of(j)) {
      if (v.index >= all.size() || all.point(v.index).level >= all.point(j).level ||
          !(v.value >= 0.0f && v.value <= 1.0f)) {
        r.fail("corrupt: a receiver relation outside the coarser levels or [0, 1]");
      }
    }
  }
  return relations;
}

std::vector<uint64_t> read_u64s(ByteReader& r, const char* what) {
  std::vector<uint64_t> values;
  r.array(values, r.u64(), 8, what, [&] { return r.u64(); });
  return values;
}

MeshlessStatistics read_statistics(ByteReader& r) {
  MeshlessStatistics s;
  s.sender_levels = r.u32();
  s.receivers_per_level = read_u64s(r, "receivers per level");
  s.links_per_level = read_u64s(r, "links per level");
  s.links = r.u64();
  s.potential_links = r.u64();
  s.refinement_stopped_at_level = int32_t(r.u32());
  s.levels_reduced = r.u32() != 0;
  s.bounces = r.u32();
  r.array(s.bounce_fractions, r.u64(), 8, "bounce fractions", [&] { return r.f64(); });
  s.coarse_spacing = r.f64();
  s.mean_free_path = r.f64();
  s.link_bytes = r.u64();
  s.placement_rays = r.u64();
  s.refinement_rays = r.u64();
  s.precompute_seconds = r.f64();
  return s;
}

std::vector<BasisPoint> read_points(ByteReader& r) {
  std::vector<BasisPoint> points;
  r.array(points, r.u64(), kPointBytes, "basis points", [&] {
    BasisPoint p;
    p.position = r.vec3();
    p.normal = r.vec3();
    p.radius = r.f32();
    p.level = r.u32();
    return p;
  });
  // BasisHierarchy sorts by level; the file holds them sorted, so indices (which S uses)
  // survive only if that sort is the identity.
  for (size_t i = 1; i < points.size(); ++i) {
    if (points[i].level < points[i - 1].level) r.fail("corrupt: basis points not sorted by level");
  }
  return points;
}

// Reads into `m` in place (Eigen 3.4's SparseMatrix has no move assignment: a returned
// matrix would be copied).
void read_operator(ByteReader& r, uint32_t expected_rows, uint32_t expected_columns,
                   SparseOperator& m) {
  const uint32_t rows = r.u32(), columns = r.u32();
  const uint64_t nonzeros = r.u64();
  if (rows != expected_rows || columns != expected_columns) {
    r.fail("corrupt: S is " + std::to_string(rows) + " x " + std::to_string(columns) +
           ", the basis needs " + std::to_string(expected_rows) + " x " +
           std::to_string(expected_columns));
  }
  if (nonzeros > uint64_t(INT32_MAX)) r.fail("corrupt: too many entries in S");
  r.need(uint64_t(columns) + 1, 4, "S column offsets");
  r.need(nonzeros, 8, "S entries");  // a row index and a value each
  // Read straight into the matrix' compressed arrays: for a large S the copies, not the
  // parsing, are what loading costs.
  m.resize(int32_t(rows), int32_t(columns));
  m.resizeNonZeros(int64_t(nonzeros));
  int32_t* outer = m.outerIndexPtr();
  int32_t* inner = m.innerIndexPtr();
  float* values = m.valuePtr();
  for (uint64_t j = 0; j <= columns; ++j) outer[j] = int32_t(r.u32());
  for (uint64_t k = 0; k < nonzeros; ++k) inner[k] = int32_t(r.u32());
  for (uint64_t k = 0; k < nonzeros; ++k) values[k] = r.f32();
  if (outer[0] != 0 || uint64_t(outer[columns]) != nonzeros) r.fail("corrupt: S offsets");
  for (uint32_t j = 0; j < columns; ++j) {
    if (outer[j + 1] < outer[j]) r.fail("corrupt: S offsets decrease");
  }
  for (uint64_t k = 0; k < nonzeros; ++k) {
    if (inner[k] < 0 || uint32_t(inner[k]) >= rows) r.fail("corrupt: S row index out of range");
    if (!std::isfinite(values[k])) r.fail("corrupt: S holds a non-finite value");
  }
}

}  // namespace

void encode_precomputation(const MeshlessPrecomputation& precomputation, ByteWriter& w) {
  write_statistics(w, precomputation.statistics);
  write_points(w, precomputation.all);
  write_transfer(w, precomputation.transfer);
  write_sky_visibility(w, precomputation.sender_sky_visibility);
  write_receiver_relations(w, precomputation.receiver_relations.get());
}

std::shared_ptr<MeshlessPrecomputation> decode_precomputation(ByteReader& r,
                                                              const JobContext* job) {
  size_t end = r.open_section(kStatistics, "statistics");
  MeshlessStatistics statistics = read_statistics(r);
  r.close_section(end, "statistics");
  end = r.open_section(kPoints, "points");
  std::vector<BasisPoint> points = read_points(r);
  r.close_section(end, "points");
  if (points.empty()) r.fail("corrupt: no basis points");
  const uint32_t levels = points.back().level + 1;
  if (statistics.sender_levels < 1 || statistics.sender_levels > levels) {
    r.fail("corrupt: " + std::to_string(statistics.sender_levels) + " sender levels of " +
           std::to_string(levels));
  }
  std::vector<BasisPoint> sender_points;
  for (const BasisPoint& p : points) {
    if (p.level < statistics.sender_levels) sender_points.push_back(p);
  }
  const uint32_t receiver_count = uint32_t(points.size());
  const uint32_t sender_count = uint32_t(sender_points.size());

  // The checksum matched, so the basis is built before S is read: S goes straight into its
  // place (see read_operator).
  std::shared_ptr<MeshlessPrecomputation> precomputation;
  try {
    precomputation = std::make_shared<MeshlessPrecomputation>(
        BasisHierarchy(std::move(points), job), BasisHierarchy(std::move(sender_points), job));
  } catch (const Error& e) {
    // The points were valid when saved; the basis refusing them means the file is damaged.
    if (e.status() != BAKEGI_ERROR_INVALID_ARGUMENT) throw;
    r.fail(std::string("corrupt: ") + e.what());
  }
  end = r.open_section(kTransfer, "transfer");
  for (SparseOperator& channel : precomputation->transfer.channel) {
    read_operator(r, 3 * receiver_count, sender_count, channel);
  }
  r.close_section(end, "transfer");
  end = r.open_section(kSkyVisibility, "sky visibility");
  precomputation->sender_sky_visibility = read_sky_visibility(r, sender_count);
  r.close_section(end, "sky visibility");
  end = r.open_section(kReceiverRelations, "receiver relations");
  precomputation->receiver_relations = read_receiver_relations(r, precomputation->all);
  r.close_section(end, "receiver relations");
  precomputation->statistics = std::move(statistics);
  return precomputation;
}

}  // namespace bakegi::meshless
