// Whether a mesh bounds a solid: its edges after welding corners by position. Antiradiance
// (§3.1) assumes every surface bounds a solid (light reaching a surface's back is never
// received); open meshes (single planes, shells with holes) and non-manifold ones break that,
// so the antiradiance hierarchy gives their triangles a back side and the solver warns.
//
// Meshes arrive as positions + indices; exporters split vertices at sharp edges and UV seams
// (Blender's flat-shaded meshes), so corners are welded first: two positions closer than
// kWeldRelativeTolerance × the mesh's bounding-box diagonal are one vertex. Then each edge of
// the welded triangles is counted (triangles collapsed by welding are skipped):
// - boundary: one triangle uses it (a hole or the rim of an open surface);
// - non-manifold: more than two triangles use it;
// - inconsistently wound: two triangles use it in the same direction (their normals
//   disagree about which side is outside).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include <glm/glm.hpp>

namespace bakegi {

struct MeshTopology {
  uint32_t welded_vertices = 0;  // vertices used, after welding (when it was needed)
  uint64_t edges = 0;
  uint64_t boundary_edges = 0;
  uint64_t non_manifold_edges = 0;
  uint64_t inconsistent_edges = 0;

  // The mesh does not bound a solid by itself.
  bool open() const { return boundary_edges > 0 || non_manifold_edges > 0; }
  bool operator==(const MeshTopology&) const = default;
};

inline constexpr float kWeldRelativeTolerance = 1e-5f;

// Indices must be in range (as scene validation checks); a trailing partial triangle is
// ignored. Linear in the corner count (hash maps).
MeshTopology analyze_mesh_topology(std::span<const glm::vec3> positions,
                                   std::span<const uint32_t> indices);

// What is wrong with a mesh, for messages: "64 open edges, 2 edges shared by more than two
// faces"; empty for a closed, consistently wound manifold.
std::string describe_topology_problems(const MeshTopology& topology);

}  // namespace bakegi
