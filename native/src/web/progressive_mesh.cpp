#include "web/progressive_mesh.h"

#include <algorithm>
#include <deque>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "mesh/mesh_simplify.h"
#include "util/error.h"

namespace bakegi {

namespace {

constexpr uint32_t kUnset = std::numeric_limits<uint32_t>::max();

// Each level keeps about a quarter of the triangles of the one above (a level of detail
// per halving of the edge length); a level that keeps more than 90% means the simplifier
// is stuck (borders, topology) and ends the chain.
constexpr double kLevelRatio = 0.25;
constexpr double kStalled = 0.9;

// Adjacency (vertex -> neighbours) of a triangle list, as compressed rows.
struct Adjacency {
  std::vector<uint32_t> start, neighbours;
  Adjacency(std::span<const uint32_t> indices, size_t vertex_count) : start(vertex_count + 1, 0) {
    for (size_t t = 0; t < indices.size(); t += 3) {
      for (int c = 0; c < 3; ++c) start[indices[t + c] + 1] += 2;
    }
    for (size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
    neighbours.resize(start.back());
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t t = 0; t < indices.size(); t += 3) {
      for (int c = 0; c < 3; ++c) {
        const uint32_t v = indices[t + c];
        neighbours[fill[v]++] = indices[t + (c + 1) % 3];
        neighbours[fill[v]++] = indices[t + (c + 2) % 3];
      }
    }
  }
  std::span<const uint32_t> of(uint32_t v) const {
    return {neighbours.data() + start[v], neighbours.data() + start[v + 1]};
  }
};

// The collapse target of `v` (dropped by the coarser level): the nearest neighbour kept by
// it, else the nearest kept vertex by breadth-first search in the finer level's triangles;
// kUnset if its piece of the mesh has none.
uint32_t collapse_target(uint32_t v, const Adjacency& finer, const std::vector<uint8_t>& kept,
                         std::span<const glm::vec3> positions) {
  std::deque<uint32_t> queue{v};
  std::vector<uint32_t> seen{v};
  while (!queue.empty()) {
    const size_t ring = queue.size();
    uint32_t best = kUnset;
    float best_distance = std::numeric_limits<float>::infinity();
    for (size_t r = 0; r < ring; ++r) {
      const uint32_t u = queue.front();
      queue.pop_front();
      for (const uint32_t w : finer.of(u)) {
        if (std::find(seen.begin(), seen.end(), w) != seen.end()) continue;
        seen.push_back(w);
        if (kept[w]) {
          const float d = glm::distance(positions[v], positions[w]);
          if (d < best_distance) best_distance = d, best = w;
        } else {
          queue.push_back(w);
        }
      }
    }
    if (best != kUnset) return best;
    if (seen.size() > 4096) break;  // a far search means a piece the coarse level dropped
  }
  return kUnset;
}

}  // namespace

ProgressiveMesh build_progressive_mesh(std::span<const glm::vec3> positions,
                                       std::span<const uint32_t> indices,
                                       size_t coarsest_triangles) {
  if (indices.size() % 3 != 0) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT, "the index count is not a multiple of 3");
  }
  for (const uint32_t i : indices) {
    if (i >= positions.size()) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "index " + std::to_string(i) + " is past the vertices");
    }
  }
  ProgressiveMesh mesh;
  if (indices.empty()) return mesh;

  // The chain of levels, fine to coarse: each level's vertices are a subset of the finer
  // one's (the simplifier collapses onto end vertices and adds none).
  std::vector<std::vector<uint32_t>> levels{{indices.begin(), indices.end()}};
  while (levels.back().size() / 3 > coarsest_triangles) {
    const std::vector<uint32_t>& finer = levels.back();
    const double ratio = std::max(kLevelRatio, double(coarsest_triangles) / (finer.size() / 3));
    SimplifiedTriangles coarser = simplify_triangles(positions, finer, ratio, 1.0f);
    if (coarser.indices.empty() || coarser.indices.size() > kStalled * finer.size()) break;
    levels.push_back(std::move(coarser.indices));
  }
  std::reverse(levels.begin(), levels.end());  // coarse first

  // Vertex order: the coarsest level's vertices, then those each finer level adds.
  const size_t vertex_count = positions.size();
  std::vector<uint32_t> streamed(vertex_count, kUnset);  // input index -> streamed index
  std::vector<uint8_t> kept(vertex_count, 0);            // in the levels so far
  for (size_t level = 0; level < levels.size(); ++level) {
    std::vector<uint32_t> added;
    for (const uint32_t v : levels[level]) {
      if (!kept[v]) kept[v] = 1, added.push_back(v);
    }
    std::sort(added.begin(), added.end());
    if (level > 0) {
      // Collapse targets against the coarser levels' vertices (kept before this level).
      std::vector<uint8_t> coarser_kept(vertex_count, 0);
      for (size_t v = 0; v < vertex_count; ++v) coarser_kept[v] = streamed[v] != kUnset;
      const Adjacency finer(levels[level], vertex_count);
      for (const uint32_t v : added) {
        const uint32_t target = collapse_target(v, finer, coarser_kept, positions);
        streamed[v] = uint32_t(mesh.original_vertex.size());
        mesh.original_vertex.push_back(v);
        mesh.parent.push_back(target == kUnset ? streamed[v] : streamed[target]);
      }
    } else {
      for (const uint32_t v : added) {
        streamed[v] = uint32_t(mesh.original_vertex.size());
        mesh.original_vertex.push_back(v);
        mesh.parent.push_back(streamed[v]);
      }
    }
    mesh.level_vertices.push_back(uint32_t(mesh.original_vertex.size()));
  }

  // Faces of the full mesh, each valid from the smallest n at which its corners resolve to
  // three distinct vertices (monotone in n: a binary search finds it).
  const size_t face_count = indices.size() / 3;
  const uint32_t total = uint32_t(mesh.original_vertex.size());
  std::vector<uint32_t> valid_at(face_count);
  auto valid = [&](size_t f, uint32_t n) {
    uint32_t r[3];
    for (int c = 0; c < 3; ++c) {
      r[c] = mesh.resolve(streamed[indices[3 * f + c]], n);
      if (r[c] == UINT32_MAX) return false;
    }
    return r[0] != r[1] && r[1] != r[2] && r[0] != r[2];
  };
  std::vector<size_t> order;
  for (size_t f = 0; f < face_count; ++f) {
    if (!valid(f, total)) continue;  // degenerate in the input itself
    uint32_t lo = 1, hi = total;     // valid at hi, find the first valid
    while (lo < hi) {
      const uint32_t mid = lo + (hi - lo) / 2;
      if (valid(f, mid)) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
    valid_at[f] = lo;
    order.push_back(f);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return valid_at[a] < valid_at[b]; });
  mesh.faces.reserve(order.size() * 3);
  for (const size_t f : order) {
    for (int c = 0; c < 3; ++c) mesh.faces.push_back(streamed[indices[3 * f + c]]);
    mesh.valid_at.push_back(valid_at[f]);
  }
  return mesh;
}

}  // namespace bakegi
