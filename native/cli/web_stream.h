// What `bakegi serve` sends (issue 16, §4 of the grid's paper): a scene folder written by
// `bakegi web export` (scene.gltf + scene.bin with progressive meshes, grid.bgivg) cut into
// numbered packets that a client asks for one after the other, grid and geometry
// interleaved:
//   grid packets     the grid's eight corners first, then a fixed number of vectors each,
//                    coarse to fine and stratified over slices (bakegi_grid_stream_order);
//   geometry packets a fixed number of vertices across every primitive, the coarsest
//                    levels of all of them first, with the faces that become valid and the
//                    vertex lookup table entries those faces need (web/progressive_mesh.h).
// Binary layout, little-endian, every packet a sequence of u32 words and f32 / byte arrays:
//   grid:     u32 kind = 1, u32 count, u32 encoding (1 quantized, 2 factored floats),
//             u32 vertex[count], then count records of 42 (quantized) or 144 bytes
//             (bakegi_grid_encode_vertices: hemispheres +x -x +y -y +z -z)
//   geometry: u32 kind = 2, u32 entries, then per entry u32 primitive, first_vertex,
//             vertex_count, has_normals, has_uvs, has_reads_grid, face_count, lookup_count;
//             f32 position[3 * vertex_count]; f32 normal[3 * vertex_count] if has_normals; f32
//             uv[2 * vertex_count] if has_uvs; f32 reads_grid[vertex_count] if has_reads_grid
//             (glTF's _BAKEGI_READS_GRID, web/corner_grid_reach.h); u32 face[3 * face_count]
//             (streamed vertex indices);
//             u32 (vertex, parent)[lookup_count]
//   visibility: u32 kind = 3, u32 bytes, then the folder's grid_visibility.bin (the grid's
//             visibility volume, grid/grid_visibility_volume.h), zero-padded to 4 bytes; sent
//             once, right after the grid's corners
// The manifest (JSON) lists the primitives, the grid and every packet's kind and bytes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bakegi::cli {

struct StreamSettings {
  uint32_t vectors_per_request = 512;   // grid vectors a request brings (after the corners)
  uint32_t vertices_per_packet = 4096;  // geometry vertices a request brings
  bool quantized = true;                // the grid's vectors as 42 bytes, else 144
};

class SceneStream {
 public:
  // Reads the folder's scene.gltf, scene.bin and grid (if named). Throws FileError for a
  // folder that is not a bakegi web export, CoreError for a bad grid.
  SceneStream(const std::filesystem::path& folder, const StreamSettings& settings);

  const std::string& manifest_json() const { return manifest_; }
  size_t packet_count() const { return packets_.size(); }
  const std::vector<uint8_t>& packet(size_t index) const { return packets_.at(index); }

 private:
  std::vector<std::vector<uint8_t>> packets_;
  std::string manifest_;
};

}  // namespace bakegi::cli
