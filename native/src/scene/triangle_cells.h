// The regular subdivision of a triangle into level² equal cells: each edge is cut into
// `level` parts and the lines through the cuts, parallel to the edges, leave level(level+1)/2
// "up" cells (oriented like the triangle) and level(level-1)/2 "down" ones. Cells are named
// in the triangle's barycentric coordinates (b1, b2) (of corners 1 and 2), so the same cell
// index means the same part of the triangle whatever its shape, and every cell has 1/level² of
// its area: a point drawn uniformly in a cell is uniform in the triangle at density
// level² / area.
//
// Cell (i, j) lies at b1 in [i, i+1]/level, b2 in [j, j+1]/level; its index is
// i (2 level - i) + 2 j (+1 for the down cell), so the cells of row i (its level - i up
// cells interleaved with its level - i - 1 down ones) are contiguous and the indices run over
// [0, level²).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace bakegi {

inline uint32_t triangle_cell_count(uint32_t level) {
  return level * level;
}

// The index of the cell that holds barycentrics (b1, b2). Points outside the triangle by
// rounding (Embree's barycentrics can be off by an ulp) go to the nearest cell.
inline uint32_t triangle_cell_containing(uint32_t level, float b1, float b2) {
  if (level <= 1) return 0;
  const float k = float(level);
  const float x = std::max(b1, 0.0f) * k, y = std::max(b2, 0.0f) * k;
  const uint32_t last = level - 1;
  const uint32_t i = std::min(uint32_t(x), last);
  uint32_t j = std::min(uint32_t(y), last);
  if (i + j > last) j = last - i;
  const bool down = i + j + 1 < level && (x - float(i)) + (y - float(j)) > 1.0f;
  return i * (2 * level - i) + 2 * j + (down ? 1 : 0);
}

// The barycentrics (b1, b2) of the three corners of cell `cell` (< level²).
inline std::array<glm::vec2, 3> triangle_cell_corners(uint32_t level, uint32_t cell) {
  if (level <= 1) return {glm::vec2(0.0f, 0.0f), glm::vec2(1.0f, 0.0f), glm::vec2(0.0f, 1.0f)};
  // Row i starts at i (2 level - i) = level² - (level - i)²: the row is level - r where r is
  // the smallest integer with r² >= level² - cell.
  const uint32_t m = level * level - cell;
  uint32_t r = uint32_t(std::sqrt(double(m)));
  while (r * r < m) ++r;
  while (r > 0 && (r - 1) * (r - 1) >= m) --r;
  const uint32_t i = level - r;
  const uint32_t offset = cell - i * (2 * level - i);
  const uint32_t j = offset / 2;
  const float k = float(level);
  const glm::vec2 a(float(i) / k, float(j) / k), b(float(i + 1) / k, float(j) / k),
      c(float(i) / k, float(j + 1) / k);
  if (offset % 2 == 0) return {a, b, c};
  return {glm::vec2(float(i + 1) / k, float(j + 1) / k), c, b};
}

// A point of cell `corners` at the cell's own barycentrics s (s.x towards its corner 1, s.y
// towards its corner 2); level-1 cells return s unchanged, bit for bit.
inline glm::vec2 triangle_cell_point(uint32_t level, const std::array<glm::vec2, 3>& corners,
                                     glm::vec2 s) {
  if (level <= 1) return s;
  return corners[0] + (corners[1] - corners[0]) * s.x + (corners[2] - corners[0]) * s.y;
}

}  // namespace bakegi
