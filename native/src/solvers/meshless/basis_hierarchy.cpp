#include "solvers/meshless/basis_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <boost/function_output_iterator.hpp>
#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "util/error.h"
#include "util/job_context.h"

namespace bakegi::meshless {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;

using Point3 = bg::model::point<float, 3, bg::cs::cartesian>;
using Box3 = bg::model::box<Point3>;
using Entry = std::pair<Box3, uint32_t>;
// Bulk-loaded (packing constructor), so the split algorithm only sets the node capacity.
// Node capacities 8, 16 and 32 measured within noise of each other (evaluate-many bench).
using Tree = bgi::rtree<Entry, bgi::quadratic<16>>;

// Points per task of the parallel DAG build: large enough that a task's R-tree queries
// dwarf the scheduling cost, small enough to balance two to sixteen cores.
constexpr size_t kBuildChunk = 512;

// The tight axis-aligned box of w_j's support, the ellipsoid squashed_distance <= r_j with
// semi-axes r_j (tangential) and r_j / (1 + kSquash) (along n_j). Along axis e the half
// extent of an ellipsoid is sqrt(sum_i a_i^2 (u_i . e)^2) = r sqrt(1 - n_e^2 (1 - s^2)),
// s = 1 / (1 + kSquash). It costs what a sphere costs but is 3x thinner across an
// axis-aligned surface, so queries near parallel walls and corners test fewer candidates.
Box3 support_box(const BasisPoint& p) {
  const float s = 1.0f / (1.0f + kSquash);
  const float shrink = 1.0f - s * s;
  glm::vec3 half;
  for (int a = 0; a < 3; ++a)
    half[a] = p.radius * std::sqrt(std::max(0.0f, 1.0f - p.normal[a] * p.normal[a] * shrink));
  // One ulp-scale pad so a query exactly on the ellipsoid's extreme is never culled by
  // rounding of the square root (the kernel is 0 there anyway, but stay conservative).
  half *= 1.0f + 1e-5f;
  const glm::vec3 lo = p.position - half, hi = p.position + half;
  return Box3(Point3(lo.x, lo.y, lo.z), Point3(hi.x, hi.y, hi.z));
}

void validate(const std::vector<BasisPoint>& points) {
  if (points.empty()) throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless basis: no points");
  if (points.size() >= size_t(UINT32_MAX))
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "meshless basis: too many points");
  uint32_t max_level = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const BasisPoint& p = points[i];
    const auto fail = [&](const char* what) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "meshless basis: point " + std::to_string(i) + ": " + what);
    };
    if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) ||
        !std::isfinite(p.position.z))
      fail("position is not finite");
    if (!(p.radius > 0.0f) || !std::isfinite(p.radius)) fail("radius must be positive");
    const float length = glm::length(p.normal);
    // Unit within float rounding of a normalize(): the weights square n . n_j.
    if (!(std::abs(length - 1.0f) <= 1e-3f)) fail("normal is not unit length");
    if (p.level >= 64) fail("level above 63");
    max_level = std::max(max_level, p.level);
  }
  std::vector<bool> present(max_level + 1, false);
  for (const BasisPoint& p : points) present[p.level] = true;
  for (uint32_t l = 0; l <= max_level; ++l)
    if (!present[l])
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "meshless basis: levels must be contiguous from 0; level " + std::to_string(l) +
                      " is empty");
}

// Per-chunk results of the DAG build, concatenated in chunk order afterwards so the
// layout does not depend on the thread count.
struct ChunkDag {
  std::vector<uint32_t> coarser_count;  // per point of the chunk
  std::vector<BasisValue> coarser;      // (k, B_k(p_j)), levels coarse to fine
  std::vector<uint32_t> same_count;     // per point of the chunk
  std::vector<uint32_t> same;           // k on j's level with w_k(p_j) > 0, k != j
};

// CSR transpose: for every j and every k in lists(j), j goes into result(k). Iterating j in
// ascending order keeps each result list sorted.
void transpose(size_t n, const std::vector<uint32_t>& offsets, const std::vector<uint32_t>& items,
               std::vector<uint32_t>& out_offsets, std::vector<uint32_t>& out_items) {
  out_offsets.assign(n + 1, 0);
  for (uint32_t k : items) ++out_offsets[k + 1];
  for (size_t i = 0; i < n; ++i) out_offsets[i + 1] += out_offsets[i];
  out_items.resize(items.size());
  std::vector<uint32_t> cursor(out_offsets.begin(), out_offsets.end() - 1);
  for (size_t j = 0; j < n; ++j)
    for (uint32_t e = offsets[j]; e < offsets[j + 1]; ++e)
      out_items[cursor[items[e]]++] = uint32_t(j);
}

}  // namespace

struct BasisHierarchy::Impl {
  std::vector<BasisPoint> points;
  std::vector<uint32_t> input_index;
  std::vector<uint32_t> level_offsets;  // level_count + 1
  std::vector<Tree> trees;              // one per level

  // CSR lists, all indexed by point.
  std::vector<uint32_t> neighbor_offsets, neighbor_items;
  std::vector<uint32_t> child_offsets, child_items;
  std::vector<uint32_t> parent_offsets, parent_items;
  std::vector<uint32_t> coarser_offsets;
  std::vector<BasisValue> coarser_items;

  void gather_weights(uint32_t level, const glm::vec3& x, const glm::vec3& n,
                      std::vector<BasisValue>& out) const {
    trees[level].query(bgi::intersects(Point3(x.x, x.y, x.z)),
                       boost::make_function_output_iterator([&](const Entry& entry) {
                         const float w = weight(points[entry.second], x, n);
                         if (w > 0.0f) out.push_back({entry.second, w});
                       }));
  }

  float gather_basis(uint32_t level, const glm::vec3& x, const glm::vec3& n,
                     std::vector<BasisValue>& out) const {
    const size_t begin = out.size();
    gather_weights(level, x, n, out);
    // The R-tree's traversal order is fixed for a given tree, but sort by index so the
    // float sum (and everything built on it) does not depend on the tree's layout.
    std::sort(out.begin() + begin, out.end(),
              [](const BasisValue& a, const BasisValue& b) { return a.index < b.index; });
    float sum = 0.0f;
    for (size_t i = begin; i < out.size(); ++i) sum += out[i].value;
    if (!(sum > 0.0f)) {
      out.resize(begin);
      return 0.0f;
    }
    const float inverse = 1.0f / sum;
    for (size_t i = begin; i < out.size(); ++i) out[i].value *= inverse;
    return sum;
  }

  void build_dag(const JobContext* job);
};

void BasisHierarchy::Impl::build_dag(const JobContext* job) {
  const size_t n = points.size();
  const size_t chunk_count = (n + kBuildChunk - 1) / kBuildChunk;
  std::vector<ChunkDag> chunks(chunk_count);
  tbb::parallel_for(size_t(0), chunk_count, [&](size_t c) {
    if (job) job->throw_if_cancelled();
    ChunkDag& chunk = chunks[c];
    const size_t begin = c * kBuildChunk, end = std::min(n, begin + kBuildChunk);
    std::vector<BasisValue> scratch;
    for (size_t j = begin; j < end; ++j) {
      const BasisPoint& p = points[j];
      const size_t before = chunk.coarser.size();
      for (uint32_t l = 0; l < p.level; ++l) gather_basis(l, p.position, p.normal, chunk.coarser);
      chunk.coarser_count.push_back(uint32_t(chunk.coarser.size() - before));
      scratch.clear();
      gather_weights(p.level, p.position, p.normal, scratch);
      // Unsorted is fine: the transpose into neighbors() visits j in order.
      const size_t same_before = chunk.same.size();
      for (const BasisValue& v : scratch)
        if (v.index != j) chunk.same.push_back(v.index);
      chunk.same_count.push_back(uint32_t(chunk.same.size() - same_before));
    }
  });

  // Concatenate: coarser_basis directly; parents = the level-(l-1) part of coarser_basis;
  // "incoming" same-level lists (k with w_k(p_j) > 0), transposed into neighbors.
  coarser_offsets.assign(n + 1, 0);
  parent_offsets.assign(n + 1, 0);
  std::vector<uint32_t> incoming_offsets(n + 1, 0), incoming_items;
  size_t coarser_total = 0, same_total = 0;
  for (const ChunkDag& chunk : chunks) {
    coarser_total += chunk.coarser.size();
    same_total += chunk.same.size();
  }
  // The CSR offsets are 32-bit: about 60 entries per point reach that only past 70M points.
  if (coarser_total >= UINT32_MAX || same_total >= UINT32_MAX)
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, "meshless basis: DAG exceeds 2^32 entries");
  coarser_items.reserve(coarser_total);
  incoming_items.reserve(same_total);
  size_t j = 0;
  for (ChunkDag& chunk : chunks) {
    size_t cursor = 0;
    for (size_t i = 0; i < chunk.coarser_count.size(); ++i, ++j) {
      const uint32_t count = chunk.coarser_count[i];
      const uint32_t level = points[j].level;
      for (uint32_t e = 0; e < count; ++e) {
        const BasisValue& v = chunk.coarser[cursor + e];
        coarser_items.push_back(v);
        if (level > 0 && points[v.index].level == level - 1) parent_items.push_back(v.index);
      }
      cursor += count;
      coarser_offsets[j + 1] = uint32_t(coarser_items.size());
      parent_offsets[j + 1] = uint32_t(parent_items.size());
      incoming_offsets[j + 1] = incoming_offsets[j] + chunk.same_count[i];
    }
    incoming_items.insert(incoming_items.end(), chunk.same.begin(), chunk.same.end());
    chunk = ChunkDag{};
  }
  // neighbors(k) = {j on k's level, j != k, w_k(p_j) > 0} = transpose of incoming;
  // children(k) = {c on level(k)+1 with w_k(p_c) > 0} = transpose of parents.
  transpose(n, incoming_offsets, incoming_items, neighbor_offsets, neighbor_items);
  transpose(n, parent_offsets, parent_items, child_offsets, child_items);
}

BasisHierarchy::BasisHierarchy(std::vector<BasisPoint> points, const JobContext* job)
    : impl_(std::make_unique<Impl>()) {
  validate(points);
  Impl& d = *impl_;
  d.input_index.resize(points.size());
  std::iota(d.input_index.begin(), d.input_index.end(), 0u);
  std::stable_sort(d.input_index.begin(), d.input_index.end(),
                   [&](uint32_t a, uint32_t b) { return points[a].level < points[b].level; });
  d.points.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) d.points[i] = points[d.input_index[i]];
  points = {};

  const uint32_t levels = d.points.back().level + 1;
  d.level_offsets.assign(levels + 1, 0);
  for (const BasisPoint& p : d.points) ++d.level_offsets[p.level + 1];
  for (uint32_t l = 0; l < levels; ++l) d.level_offsets[l + 1] += d.level_offsets[l];

  d.trees.resize(levels);
  tbb::parallel_for(uint32_t(0), levels, [&](uint32_t l) {
    std::vector<Entry> entries;
    entries.reserve(d.level_offsets[l + 1] - d.level_offsets[l]);
    for (uint32_t j = d.level_offsets[l]; j < d.level_offsets[l + 1]; ++j)
      entries.emplace_back(support_box(d.points[j]), j);
    d.trees[l] = Tree(entries.begin(), entries.end());  // STR bulk load
  });
  d.build_dag(job);
}

BasisHierarchy::~BasisHierarchy() = default;
BasisHierarchy::BasisHierarchy(BasisHierarchy&&) noexcept = default;
BasisHierarchy& BasisHierarchy::operator=(BasisHierarchy&&) noexcept = default;

size_t BasisHierarchy::size() const {
  return impl_->points.size();
}
uint32_t BasisHierarchy::level_count() const {
  return uint32_t(impl_->trees.size());
}
std::span<const BasisPoint> BasisHierarchy::points() const {
  return impl_->points;
}
const BasisPoint& BasisHierarchy::point(uint32_t index) const {
  return impl_->points[index];
}
uint32_t BasisHierarchy::input_index(uint32_t index) const {
  return impl_->input_index[index];
}
uint32_t BasisHierarchy::level_begin(uint32_t level) const {
  return impl_->level_offsets[level];
}
uint32_t BasisHierarchy::level_end(uint32_t level) const {
  return impl_->level_offsets[level + 1];
}

void BasisHierarchy::gather_weights(uint32_t level, const glm::vec3& x, const glm::vec3& n,
                                    std::vector<BasisValue>& out) const {
  if (level >= level_count()) return;
  impl_->gather_weights(level, x, n, out);
}

float BasisHierarchy::gather_basis(uint32_t level, const glm::vec3& x, const glm::vec3& n,
                                   std::vector<BasisValue>& out) const {
  if (level >= level_count()) return 0.0f;
  return impl_->gather_basis(level, x, n, out);
}

std::span<const uint32_t> BasisHierarchy::neighbors(uint32_t index) const {
  const Impl& d = *impl_;
  return {d.neighbor_items.data() + d.neighbor_offsets[index],
          d.neighbor_offsets[index + 1] - d.neighbor_offsets[index]};
}

std::span<const uint32_t> BasisHierarchy::children(uint32_t index) const {
  const Impl& d = *impl_;
  return {d.child_items.data() + d.child_offsets[index],
          d.child_offsets[index + 1] - d.child_offsets[index]};
}

std::span<const uint32_t> BasisHierarchy::parents(uint32_t index) const {
  const Impl& d = *impl_;
  return {d.parent_items.data() + d.parent_offsets[index],
          d.parent_offsets[index + 1] - d.parent_offsets[index]};
}

std::span<const BasisValue> BasisHierarchy::coarser_basis(uint32_t index) const {
  const Impl& d = *impl_;
  return {d.coarser_items.data() + d.coarser_offsets[index],
          d.coarser_offsets[index + 1] - d.coarser_offsets[index]};
}

size_t BasisHierarchy::memory_bytes() const {
  const Impl& d = *impl_;
  const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  size_t total = sizeof(Impl) + bytes(d.points) + bytes(d.input_index) + bytes(d.level_offsets) +
                 bytes(d.neighbor_offsets) + bytes(d.neighbor_items) + bytes(d.child_offsets) +
                 bytes(d.child_items) + bytes(d.parent_offsets) + bytes(d.parent_items) +
                 bytes(d.coarser_offsets) + bytes(d.coarser_items);
  // R-tree nodes: the leaves hold the entries; inner nodes add about 1/(fanout - 1) of
  // that in boxes and pointers (fill of the bulk-loaded tree is near the capacity 16).
  for (const Tree& tree : d.trees) total += tree.size() * (sizeof(Entry) + sizeof(void*)) * 17 / 15;
  return total;
}

}  // namespace bakegi::meshless
