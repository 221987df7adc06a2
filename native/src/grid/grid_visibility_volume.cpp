#include "grid/grid_visibility_volume.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <zlib.h>

#include "scene/ray_tracer.h"
#include "scene/scene.h"
#include "util/byte_stream.h"
#include "util/error.h"

namespace bakegi {

namespace {

constexpr char kMagic[8] = {'B', 'G', 'I', 'V', 'I', 'S', '1', '\0'};

// The lowest vertex of the trilinear cell at grid coordinates g (as grid_interpolation.cpp's
// linear taps: clamped into the grid, the last cell past its end).
std::array<uint32_t, 3> cell_of(const glm::vec3& g, const std::array<uint32_t, 3>& resolution) {
  std::array<uint32_t, 3> lo;
  for (int a = 0; a < 3; ++a) {
    const float x = std::isfinite(g[a]) ? std::clamp(g[a], 0.0f, float(resolution[a] - 1)) : 0.0f;
    lo[a] = std::min(uint32_t(x), resolution[a] - 2);
  }
  return lo;
}

// The subvoxel holding grid coordinates g (clamped into the volume).
size_t subvoxel_of(const glm::vec3& g, const GridVisibilityVolume& volume) {
  size_t index[3];
  for (int a = 0; a < 3; ++a) {
    const float x = std::isfinite(g[a]) ? (g[a] + 0.5f) * float(volume.subdivision) : 0.0f;
    index[a] = size_t(std::clamp(x, 0.0f, float(volume.size[a] - 1)));
  }
  return (index[2] * volume.size[1] + index[1]) * volume.size[0] + index[0];
}

struct SubvoxelVisibility {
  uint8_t mask = 0;
  uint8_t fallback = kNoFallback;
  bool has_open_point = false;
};

// What the points of one subvoxel see (the header's rules).
SubvoxelVisibility subvoxel_visibility(const IrradianceVectorGrid& grid, const Scene& scene,
                                       const RayTracer& tracer, const glm::vec3& centre,
                                       const std::array<uint32_t, 3>& lo, const glm::vec3& step) {
  const GridLayout& layout = grid.layout;
  SubvoxelVisibility result;
  glm::vec3 open_points[9];
  int open_count = 0;
  for (int s = 0; s < 9; ++s) {
    // The centre first: where it sees all 8 vertices from open space nothing can add to that.
    if (s == 1 && result.mask == 0xff) break;
    const glm::vec3 point =
        s == 0 ? centre
               : centre + 0.25f * step *
                              glm::vec3((s - 1) & 1 ? 1.0f : -1.0f, (s - 1) & 2 ? 1.0f : -1.0f,
                                        (s - 1) & 4 ? 1.0f : -1.0f);
    uint8_t seen = 0;
    bool inside = false;
    for (int c = 0; c < 8 && !inside; ++c) {
      const uint32_t i = lo[0] + (c & 1), j = lo[1] + ((c >> 1) & 1), k = lo[2] + ((c >> 2) & 1);
      const glm::vec3 to = layout.vertex_position(i, j, k) - point;
      const float distance = glm::length(to);
      if (distance > 1e-6f) {
        const Hit hit = tracer.intersect(Ray{point, to / distance, 0.0f, distance});
        if (hit.hit) {
          // A back face first: the point is inside a solid (or under a one-sided surface).
          inside = glm::dot(scene.triangles[hit.triangle].face_normal, to) > 0.0f;
          continue;
        }
      }
      // Nothing between the point and a vertex inside geometry (the grid's gather found it
      // there): the point is inside the same solid.
      if (!grid.valid[layout.vertex_index(i, j, k)]) {
        inside = true;
        continue;
      }
      seen |= uint8_t(1u << c);
    }
    if (inside) continue;
    result.mask |= seen;
    open_points[open_count++] = point;
  }
  result.has_open_point = open_count > 0;
  if (result.mask != 0 || open_count == 0) return result;
  // None of the cell's vertices: the nearest of the 4^3 around it that an open point sees.
  struct Candidate {
    float distance;
    uint8_t code;
    uint32_t i, j, k;
  };
  Candidate candidates[64];
  int count = 0;
  for (int dk = -1; dk <= 2; ++dk) {
    for (int dj = -1; dj <= 2; ++dj) {
      for (int di = -1; di <= 2; ++di) {
        const int64_t i = int64_t(lo[0]) + di, j = int64_t(lo[1]) + dj, k = int64_t(lo[2]) + dk;
        if (i < 0 || j < 0 || k < 0 || i >= layout.resolution[0] || j >= layout.resolution[1] ||
            k >= layout.resolution[2]) {
          continue;
        }
        if (!grid.valid[layout.vertex_index(uint32_t(i), uint32_t(j), uint32_t(k))]) continue;
        const glm::vec3 at = layout.vertex_position(uint32_t(i), uint32_t(j), uint32_t(k));
        candidates[count++] = {glm::length(at - centre),
                               uint8_t((di + 1) | (dj + 1) << 2 | (dk + 1) << 4), uint32_t(i),
                               uint32_t(j), uint32_t(k)};
      }
    }
  }
  std::sort(candidates, candidates + count,
            [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
  for (int n = 0; n < count; ++n) {
    const glm::vec3 at = layout.vertex_position(candidates[n].i, candidates[n].j, candidates[n].k);
    for (int s = 0; s < open_count; ++s) {
      const glm::vec3 to = at - open_points[s];
      const float distance = glm::length(to);
      if (distance <= 1e-6f ||
          !tracer.occluded(Ray{open_points[s], to / distance, 0.0f, distance})) {
        result.fallback = candidates[n].code;
        return result;
      }
    }
  }
  return result;
}

}  // namespace

uint32_t page_visibility_subdivision(const GridLayout& layout) {
  const uint32_t cells =
      std::max({layout.resolution[0], layout.resolution[1], layout.resolution[2]});
  // At 16 cells or fewer the finest (8): gaps thinner than a subvoxel share its mask, and at
  // 16 cells 8 a cell read the office's nooks far better than 4 (docs/ivg.md) for a volume
  // still under 2 M subvoxels; above that about 1/64 of the longest side.
  if (cells <= 16) return 8;
  const uint32_t half = (32 + cells - 1) / cells;  // ceil(32 / cells)
  return std::clamp(2 * half, 2u, 8u);
}

float visibility_read_offset(const GridLayout& layout, uint32_t subdivision) {
  const glm::vec3 cell = layout.cell_size();
  return std::max({cell.x, cell.y, cell.z}) / float(std::max(subdivision, 1u));
}

GridVisibilityVolume build_grid_visibility_volume(const IrradianceVectorGrid& grid,
                                                  const Scene& scene, const RayTracer& tracer,
                                                  uint32_t subdivision, bool world_lit,
                                                  const std::function<bool()>& cancelled) {
  if (subdivision < 2 || subdivision > 8 || subdivision % 2 != 0) {
    throw Error(
        BAKEGI_ERROR_INVALID_ARGUMENT,
        "visibility volume: subdivision " + std::to_string(subdivision) + " is not 2, 4, 6 or 8");
  }
  const GridLayout& layout = grid.layout;
  for (int a = 0; a < 3; ++a) {
    if (layout.resolution[a] < 2) {
      throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                  "visibility volume: the grid needs 2 vertices or more along every axis");
    }
  }
  GridVisibilityVolume volume;
  volume.subdivision = subdivision;
  for (int a = 0; a < 3; ++a) volume.size[a] = layout.resolution[a] * subdivision;
  const size_t count = volume.subvoxel_count();
  if (layout.vertex_count() > kMaxVisibilitySubvoxels ||
      count / (size_t(subdivision) * subdivision * subdivision) != layout.vertex_count() ||
      count > kMaxVisibilitySubvoxels) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY,
                "visibility volume: " + std::to_string(layout.vertex_count()) +
                    " grid vertices cut " + std::to_string(subdivision) + "^3 pass its limit of " +
                    std::to_string(kMaxVisibilitySubvoxels) + " subvoxels");
  }
  volume.codes.assign(2 * count, 0);
  std::vector<uint8_t> has_open_point(count, 0);
  const glm::vec3 step = layout.cell_size() / float(subdivision);
  const size_t nx = volume.size[0], ny = volume.size[1], nz = volume.size[2];
  // The subvoxel's centre in grid coordinates (vertex (i, j, k) at (i, j, k)).
  const auto centre_of = [&](size_t x, size_t y, size_t z) {
    return (glm::vec3(float(x), float(y), float(z)) + 0.5f) / float(subdivision) - 0.5f;
  };
  std::atomic<bool> stop{false};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nz), [&](const tbb::blocked_range<size_t>& b) {
    for (size_t z = b.begin(); z != b.end(); ++z) {
      if (stop.load(std::memory_order_relaxed) || (cancelled && cancelled())) {
        stop = true;
        return;
      }
      for (size_t y = 0; y < ny; ++y) {
        for (size_t x = 0; x < nx; ++x) {
          const glm::vec3 g = centre_of(x, y, z);
          const glm::vec3 centre = layout.bounds_min + (g + 0.5f) * layout.cell_size();
          const SubvoxelVisibility v =
              subvoxel_visibility(grid, scene, tracer, centre, cell_of(g, layout.resolution), step);
          const size_t id = (z * ny + y) * nx + x;
          volume.codes[2 * id] = v.mask;
          volume.codes[2 * id + 1] = v.fallback;
          has_open_point[id] = v.has_open_point;
        }
      }
    }
  });
  if (stop) throw Error(BAKEGI_ERROR_CANCELLED, "cancelled");
  // Subvoxels whose points are all inside solids (a wall's face along their edge): the union
  // of their face neighbours' in the same cell, from the values above only.
  const std::vector<uint8_t> first = volume.codes;
  for (size_t z = 0; z < nz; ++z) {
    for (size_t y = 0; y < ny; ++y) {
      for (size_t x = 0; x < nx; ++x) {
        const size_t id = (z * ny + y) * nx + x;
        if (has_open_point[id]) continue;
        const std::array<uint32_t, 3> lo = cell_of(centre_of(x, y, z), layout.resolution);
        uint8_t mask = 0, fallback = kNoFallback;
        bool any_open_neighbour = false;
        const int64_t offsets[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                       {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
        for (const auto& d : offsets) {
          const int64_t X = int64_t(x) + d[0], Y = int64_t(y) + d[1], Z = int64_t(z) + d[2];
          if (X < 0 || Y < 0 || Z < 0 || X >= int64_t(nx) || Y >= int64_t(ny) || Z >= int64_t(nz)) {
            continue;
          }
          const size_t other = (size_t(Z) * ny + size_t(Y)) * nx + size_t(X);
          if (!has_open_point[other] ||
              cell_of(centre_of(size_t(X), size_t(Y), size_t(Z)), layout.resolution) != lo) {
            continue;
          }
          mask |= first[2 * other];
          if (fallback == kNoFallback) fallback = first[2 * other + 1];
          any_open_neighbour = true;
        }
        if (!any_open_neighbour) {
          // No open point to judge from: deep inside a solid, or where the grid's box ends on
          // a surface facing out (a room's outer wall, the top of the tallest object), whose
          // points read one subvoxel out, clamped into the box. Out there is only the world:
          // under a sky such a surface is lit, so the paper's reading (all 8 vertices);
          // under a black world it is dark, so nothing (unsure).
          mask = world_lit ? 0xff : 0;
          fallback = kNoFallback;
        }
        volume.codes[2 * id] = mask;
        volume.codes[2 * id + 1] = mask == 0 ? fallback : kNoFallback;
      }
    }
  }
  return volume;
}

glm::vec3 evaluate_grid_with_volume(const IrradianceVectorGrid& grid,
                                    const GridVisibilityVolume& volume, const glm::vec3& position,
                                    const glm::vec3& normal, GridDirectionalWeights weights,
                                    bool* unsure) {
  if (unsure) *unsure = false;
  const float length = glm::length(normal);
  if (!(length > 0.0f) || !std::isfinite(length)) return glm::vec3(0.0f);
  const glm::vec3 n = normal / length;
  const GridLayout& layout = grid.layout;
  const glm::vec3 q = position + visibility_read_offset(layout, volume.subdivision) * n;
  glm::vec3 g = layout.grid_coordinates(q);
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(g[a])) g[a] = 0.0f;
  }
  const size_t id = subvoxel_of(g, volume);
  const uint8_t mask = volume.codes[2 * id];
  const uint8_t fallback = volume.codes[2 * id + 1];
  const std::array<uint32_t, 3> lo = cell_of(g, layout.resolution);
  if (mask == 0) {
    if (fallback == kNoFallback) {
      if (unsure) *unsure = true;
      return glm::vec3(0.0f);
    }
    const size_t vertex =
        layout.vertex_index(lo[0] + (fallback & 3) - 1, lo[1] + ((fallback >> 2) & 3) - 1,
                            lo[2] + ((fallback >> 4) & 3) - 1);
    const float one = 1.0f;
    return blend_vertices(grid, n, std::span<const size_t>(&vertex, 1),
                          std::span<const float>(&one, 1), weights);
  }
  size_t vertices[8];
  float spatial[8];
  int count = 0;
  float total = 0.0f;
  for (int c = 0; c < 8; ++c) {
    if (!((mask >> c) & 1)) continue;
    const uint32_t offset[3] = {uint32_t(c & 1), uint32_t((c >> 1) & 1), uint32_t((c >> 2) & 1)};
    float w = 1.0f;
    for (int a = 0; a < 3; ++a) {
      const float t = std::clamp(g[a], 0.0f, float(layout.resolution[a] - 1)) - float(lo[a]);
      w *= offset[a] ? t : 1.0f - t;
    }
    // Never 0, so that a point on the seen vertices' zero-weight side still reads them
    // (equally); the page's shader does the same.
    w = std::max(w, 1e-6f);
    vertices[count] = layout.vertex_index(lo[0] + offset[0], lo[1] + offset[1], lo[2] + offset[2]);
    spatial[count++] = w;
    total += w;
  }
  for (int i = 0; i < count; ++i) spatial[i] /= total;
  return blend_vertices(grid, n, std::span<const size_t>(vertices, count),
                        std::span<const float>(spatial, count), weights);
}

void evaluate_grid_with_volume(const IrradianceVectorGrid& grid, const GridVisibilityVolume& volume,
                               std::span<const glm::vec3> positions,
                               std::span<const glm::vec3> normals, GridDirectionalWeights weights,
                               std::span<glm::vec3> out, std::span<uint8_t> unsure) {
  if (normals.size() != positions.size() || out.size() != positions.size() ||
      (!unsure.empty() && unsure.size() != positions.size())) {
    throw Error(BAKEGI_ERROR_INTERNAL, "grid evaluation: sizes of the point arrays differ");
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 4096),
                    [&](const tbb::blocked_range<size_t>& block) {
                      for (size_t i = block.begin(); i != block.end(); ++i) {
                        bool none = false;
                        out[i] = evaluate_grid_with_volume(grid, volume, positions[i], normals[i],
                                                           weights, &none);
                        if (!unsure.empty()) unsure[i] = none ? 1 : 0;
                      }
                    });
}

std::vector<uint8_t> encode_visibility_file(const GridVisibilityVolume& volume,
                                            const GridLayout& layout) {
  uLongf compressed_size = compressBound(uLong(volume.codes.size()));
  std::vector<uint8_t> compressed(compressed_size);
  if (compress2(compressed.data(), &compressed_size, volume.codes.data(),
                uLong(volume.codes.size()), Z_BEST_COMPRESSION) != Z_OK) {
    throw Error(BAKEGI_ERROR_OUT_OF_MEMORY, "visibility volume: compression failed");
  }
  ByteWriter w;
  w.bytes.insert(w.bytes.end(), kMagic, kMagic + 8);
  w.u32(volume.subdivision);
  for (int a = 0; a < 3; ++a) w.u32(volume.size[a]);
  for (int a = 0; a < 3; ++a) w.u32(layout.resolution[a]);
  w.u64(volume.codes.size());
  w.bytes.insert(w.bytes.end(), compressed.begin(), compressed.begin() + compressed_size);
  return std::move(w.bytes);
}

GridVisibilityVolume decode_visibility_file(std::span<const uint8_t> bytes,
                                            const GridLayout& layout) {
  ByteReader r(bytes, "visibility volume");
  r.need(8, 1, "the magic");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0) r.fail("not a bakegi visibility volume");
  for (int i = 0; i < 8; ++i) r.u8();
  GridVisibilityVolume volume;
  volume.subdivision = r.u32();
  if (volume.subdivision < 2 || volume.subdivision > 8 || volume.subdivision % 2 != 0) {
    r.fail("subdivision " + std::to_string(volume.subdivision) + " is not 2, 4, 6 or 8");
  }
  for (int a = 0; a < 3; ++a) volume.size[a] = r.u32();
  for (int a = 0; a < 3; ++a) {
    if (r.u32() != layout.resolution[a] ||
        volume.size[a] != uint64_t(layout.resolution[a]) * volume.subdivision) {
      r.fail("made for another grid (its resolution differs)");
    }
  }
  const uint64_t raw = r.u64();
  if (raw != 2 * volume.subvoxel_count()) r.fail("corrupt: its size does not match its subvoxels");
  volume.codes.resize(raw);
  uLongf out_size = uLongf(raw);
  const int status =
      uncompress(volume.codes.data(), &out_size, bytes.data() + r.position(), uLong(r.left()));
  if (status != Z_OK || out_size != raw) r.fail("corrupt: its compressed codes do not unpack");
  return volume;
}

}  // namespace bakegi
