#include "scene/mesh_topology.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace bakegi {
namespace {

// Cells of the welding grid per axis fit 21 bits: extent / (2 tolerance) = 5e4 cells at most.
constexpr uint64_t kCellBits = 21;
constexpr int64_t kCellMask = (int64_t(1) << kCellBits) - 1;

uint64_t cell_key(int64_t x, int64_t y, int64_t z) {
  return (uint64_t(x & kCellMask) << (2 * kCellBits)) | (uint64_t(y & kCellMask) << kCellBits) |
         uint64_t(z & kCellMask);
}

// Open-addressing hash map from a key to a uint32 value (linear probing, power-of-two size,
// at most half full): several times faster than std::unordered_map for the millions of
// corners of a large mesh, which would otherwise dominate scene building.
template <typename Key, typename Hash>
class FlatMap {
 public:
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

  explicit FlatMap(size_t expected) {
    size_t size = 16;
    while (size < 2 * expected) size *= 2;
    keys_.resize(size);
    values_.assign(size, kNone);
    mask_ = size - 1;
  }
  // The value slot of `key`, inserting kNone when it is new (never more than `expected` keys).
  uint32_t& operator[](const Key& key) {
    for (size_t i = Hash{}(key)&mask_;; i = (i + 1) & mask_) {
      if (values_[i] == kNone) {
        keys_[i] = key;
        return values_[i];
      }
      if (keys_[i] == key) return values_[i];
    }
  }
  uint32_t find(const Key& key) const {
    for (size_t i = Hash{}(key)&mask_;; i = (i + 1) & mask_) {
      if (values_[i] == kNone) return kNone;
      if (keys_[i] == key) return values_[i];
    }
  }

 private:
  std::vector<Key> keys_;
  std::vector<uint32_t> values_;
  size_t mask_ = 0;
};

uint64_t mix(uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  return h ^ (h >> 33);
}

struct PositionBits {
  uint32_t x, y, z;  // the float bits, filled by memcpy (so trivially constructible)
  bool operator==(const PositionBits&) const = default;
};
struct PositionBitsHash {
  size_t operator()(const PositionBits& p) const {
    return size_t(mix((uint64_t(p.x) << 32 | p.y) ^ mix(p.z)));
  }
};
struct KeyHash {
  size_t operator()(uint64_t key) const { return size_t(mix(key)); }
};

// Maps every position to a welded vertex id: the first earlier position within `tolerance`,
// else a new id. Exact copies (what exporters that split vertices mostly produce) are found
// with one lookup; other positions search a grid of cells 2 × tolerance wide, where every
// position within tolerance lies in one of the 2 × 2 × 2 cells nearest to it.
std::vector<uint32_t> weld(std::span<const glm::vec3> positions, uint32_t& welded_count) {
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> ids(positions.size());
  welded_count = 0;
  if (positions.empty()) return ids;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const glm::vec3& p : positions) {
    lo = glm::min(lo, glm::dvec3(p));
    hi = glm::max(hi, glm::dvec3(p));
  }
  const double diagonal = glm::length(hi - lo);
  // A mesh of one repeated point welds into one vertex.
  const double tolerance = diagonal > 0.0 ? double(kWeldRelativeTolerance) * diagonal : 1.0;
  const double tolerance2 = tolerance * tolerance;
  const double cell = 2.0 * tolerance;

  FlatMap<PositionBits, PositionBitsHash> exact(positions.size());  // position -> vertex
  FlatMap<uint64_t, KeyHash> first_in_cell(positions.size());       // cell -> first welded vertex
  std::vector<uint32_t> next_in_cell;                               // per welded vertex, or kNone
  std::vector<glm::dvec3> welded_positions;
  for (size_t i = 0; i < positions.size(); ++i) {
    PositionBits bits;
    std::memcpy(&bits, &positions[i], sizeof(bits));
    uint32_t& known = exact[bits];
    if (known != kNone) {
      ids[i] = known;
      continue;
    }
    const glm::dvec3 p(positions[i]);
    const glm::dvec3 g = (p - lo) / cell;
    const glm::dvec3 base = glm::floor(g);
    // The neighbour cell on each axis is the one on the side p is nearer to.
    const glm::ivec3 step(g.x - base.x < 0.5 ? -1 : 1, g.y - base.y < 0.5 ? -1 : 1,
                          g.z - base.z < 0.5 ? -1 : 1);
    const int64_t cx = int64_t(base.x), cy = int64_t(base.y), cz = int64_t(base.z);
    uint32_t found = kNone;
    for (int k = 0; k < 8 && found == kNone; ++k) {
      const uint32_t first = first_in_cell.find(cell_key(
          cx + (k & 1 ? step.x : 0), cy + (k & 2 ? step.y : 0), cz + (k & 4 ? step.z : 0)));
      for (uint32_t v = first; v != kNone; v = next_in_cell[v]) {
        const glm::dvec3 d = welded_positions[v] - p;
        if (glm::dot(d, d) <= tolerance2) {
          found = v;
          break;
        }
      }
    }
    if (found == kNone) {
      found = uint32_t(welded_positions.size());
      welded_positions.push_back(p);
      uint32_t& head = first_in_cell[cell_key(cx, cy, cz)];
      next_in_cell.push_back(head);  // kNone for a new cell
      head = found;
    }
    known = found;
    ids[i] = found;
  }
  welded_count = uint32_t(welded_positions.size());
  return ids;
}

// Counts the edges of the triangles over vertex ids `ids` (one per position, each below
// `vertex_count`). Half-edges are bucketed by their smaller vertex (a counting sort, linear and
// cache-friendly, unlike a hash map over millions of edges), then each small bucket is sorted
// by the other vertex and its runs are the edges.
// When `on_boundary` is given, it gets a 1 for both vertices of every boundary edge.
void count_edges(std::span<const uint32_t> ids, uint32_t vertex_count,
                 std::span<const uint32_t> indices, MeshTopology& topology,
                 std::vector<uint8_t>* on_boundary = nullptr) {
  std::vector<uint32_t> bucket_start(size_t(vertex_count) + 1, 0);
  auto for_each_half_edge = [&](auto&& visit) {
    for (size_t t = 0; t + 3 <= indices.size(); t += 3) {
      const uint32_t v[3] = {ids[indices[t]], ids[indices[t + 1]], ids[indices[t + 2]]};
      if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;  // collapsed by welding
      for (int e = 0; e < 3; ++e) visit(v[e], v[(e + 1) % 3]);
    }
  };
  for_each_half_edge([&](uint32_t a, uint32_t b) { ++bucket_start[std::min(a, b) + 1]; });
  for (size_t v = 0; v < vertex_count; ++v) bucket_start[v + 1] += bucket_start[v];
  // Per half-edge: the larger vertex, shifted left once, with the direction in bit 0.
  std::vector<uint64_t> half_edges(bucket_start.back());
  std::vector<uint32_t> fill(bucket_start.begin(), bucket_start.end() - 1);
  for_each_half_edge([&](uint32_t a, uint32_t b) {
    half_edges[fill[std::min(a, b)]++] = (uint64_t(std::max(a, b)) << 1) | (a < b ? 1u : 0u);
  });
  topology.edges = topology.boundary_edges = topology.non_manifold_edges =
      topology.inconsistent_edges = 0;
  for (size_t v = 0; v < vertex_count; ++v) {
    const auto begin = half_edges.begin() + bucket_start[v];
    const auto end = half_edges.begin() + bucket_start[v + 1];
    std::sort(begin, end);
    for (auto run = begin; run != end;) {
      auto run_end = run;
      uint32_t forward = 0;
      while (run_end != end && (*run_end >> 1) == (*run >> 1)) forward += uint32_t(*run_end++ & 1);
      const size_t count = size_t(run_end - run);
      ++topology.edges;
      if (count == 1) {
        ++topology.boundary_edges;
        if (on_boundary != nullptr) (*on_boundary)[v] = (*on_boundary)[*run >> 1] = 1;
      } else if (count > 2) {
        ++topology.non_manifold_edges;
      } else if (forward != 1) {
        ++topology.inconsistent_edges;
      }
      run = run_end;
    }
  }
}

}  // namespace

MeshTopology analyze_mesh_topology(std::span<const glm::vec3> positions,
                                   std::span<const uint32_t> indices) {
  MeshTopology topology;
  // Exporters that share vertices (the add-on sends Blender's vertices and loop triangles)
  // give meshes whole as they are; only corners on open edges can be copies to weld (split
  // vertices leave open edges), so welding, the costly part, runs on those alone.
  const uint32_t vertex_count = uint32_t(positions.size());
  std::vector<uint32_t> ids(vertex_count);
  for (uint32_t i = 0; i < vertex_count; ++i) ids[i] = i;
  std::vector<uint8_t> on_boundary(vertex_count, 0);
  count_edges(ids, vertex_count, indices, topology, &on_boundary);
  if (topology.boundary_edges > 0) {
    std::vector<glm::vec3> boundary_positions;
    std::vector<uint32_t> boundary_vertices;
    for (uint32_t i = 0; i < vertex_count; ++i) {
      if (!on_boundary[i]) continue;
      boundary_vertices.push_back(i);
      boundary_positions.push_back(positions[i]);
    }
    uint32_t welded_count = 0;
    const std::vector<uint32_t> welded = weld(boundary_positions, welded_count);
    // Welded boundary vertices first, then every other vertex with an id of its own.
    uint32_t next = welded_count;
    for (uint32_t i = 0; i < vertex_count; ++i) {
      if (!on_boundary[i]) ids[i] = next++;
    }
    for (size_t k = 0; k < boundary_vertices.size(); ++k) ids[boundary_vertices[k]] = welded[k];
    count_edges(ids, next, indices, topology);
  }
  std::vector<uint8_t> used(vertex_count, 0);
  for (const uint32_t i : indices) used[ids[i]] = 1;
  topology.welded_vertices = uint32_t(std::count(used.begin(), used.end(), uint8_t(1)));
  return topology;
}

std::string describe_topology_problems(const MeshTopology& topology) {
  std::string what;
  auto add = [&](uint64_t count, const char* text) {
    if (count == 0) return;
    if (!what.empty()) what += ", ";
    what += std::to_string(count) + text;
  };
  add(topology.boundary_edges, " open edges");
  add(topology.non_manifold_edges, " edges shared by more than two faces");
  add(topology.inconsistent_edges, " edges between faces of opposite winding");
  return what;
}

}  // namespace bakegi
