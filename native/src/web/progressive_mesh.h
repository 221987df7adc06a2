// A progressive mesh for streaming (Pacanowski et al. 2008, §4.2, after Melax 1998): edge
// collapses onto one of the edge's end vertices, encoded on the original mesh as
//  - its vertices reordered so that those of coarser levels come first,
//  - a vertex lookup table: per vertex, the earlier vertex it collapses onto (its parent),
//  - its faces ordered by the vertex count at which they become valid.
// A client holding the first n vertices draws each received face with every corner v >= n
// replaced by parent[v] (repeatedly) and skips nothing: a face is streamed only once its
// corners map to three distinct vertices, which stays true as n grows.
//
// The collapses come from meshoptimizer's simplifier (mesh/mesh_simplify.h), run as a chain
// of levels each a quarter of the one above; a vertex that a coarser level drops collapses
// onto its nearest neighbour (in the finer level's triangles) that the coarser level keeps.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace bakegi {

struct ProgressiveMesh {
  std::vector<uint32_t> original_vertex;  // per streamed vertex: its index in the input
  std::vector<uint32_t> parent;           // per streamed vertex: its collapse target (< it), or
                                          // itself for a vertex of the coarsest level
  std::vector<uint32_t> faces;            // 3 per face, streamed vertex indices, in stream order
  std::vector<uint32_t> valid_at;         // per face: the vertex count from which it is valid
  std::vector<uint32_t> level_vertices;   // vertex count at the end of each level, coarse first

  // The vertex a client with the first n vertices draws for streamed vertex v; UINT32_MAX
  // when none of its ancestors has arrived (a root not yet received).
  uint32_t resolve(uint32_t v, uint32_t n) const {
    while (v >= n) {
      if (parent[v] == v) return UINT32_MAX;
      v = parent[v];
    }
    return v;
  }
};

// The progressive mesh of `indices` (3 per triangle into `positions`; unreferenced vertices
// are left out). Levels stop at `coarsest_triangles` or when the simplifier stalls. Throws
// Error(INVALID_ARGUMENT) for indices out of range.
ProgressiveMesh build_progressive_mesh(std::span<const glm::vec3> positions,
                                       std::span<const uint32_t> indices,
                                       size_t coarsest_triangles = 64);

}  // namespace bakegi
