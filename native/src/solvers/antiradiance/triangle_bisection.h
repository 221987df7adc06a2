// Cutting a sliver into pieces by longest-edge bisection (Rivara): a triangle with an edge
// longer than the piece size is cut from the midpoint of its longest edge to the opposite
// corner, and both halves again, until every edge is at most the piece size.
//
// Fan triangulations of n-gons (a floor, a wall with a window hole) are made of slivers:
// needles and wedges metres long and centimetres wide. 4-way midpoint splits halve every edge
// and turn one into 4^k needles (on a furnished room 115k of 123k patches at 0.5 m came from
// 1,500 slivers). Their bisection pieces are short in every direction and group with their
// neighbours like small triangles (triangle_grouping.h), so a fanned floor becomes patches of
// the patch size. Bisection keeps shapes well conditioned and halves the area exactly.
//
// Everything is done in the triangle's barycentric coordinates (b1, b2): corner 0 at (0, 0),
// corner 1 at (1, 0), corner 2 at (0, 1); lengths are measured in the world. A piece is named
// by its path from the root, code = (1 << depth) | bits (bit k: the second half at step k), so
// the piece a point lies in is found by descending the same cuts (PatchLocator).
#pragma once

#include <cstdint>
#include <functional>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace bakegi::antiradiance {

// Deeper cuts than this are not made; the path code then still fits 31 bits.
inline constexpr int kMaxBisectionDepth = 30;

struct BisectionPiece {
  glm::vec2 corners[3];  // barycentric (b1, b2), counter-clockwise like the triangle
  uint32_t code = 1;     // (1 << depth) | path bits
  int depth = 0;
};

// Calls `piece` for every piece of `t` at this piece size, depth first (first half first).
void bisect_triangle(const Triangle& t, float piece_size,
                     const std::function<void(const BisectionPiece&)>& piece);

// The number of pieces bisect_triangle makes, or cap + 1 when there would be more (counting
// stops there, so absurd sizes cost no time).
uint64_t bisection_piece_count(const Triangle& t, float piece_size, uint64_t cap);

// The code of the piece of `t` holding barycentrics (b1, b2) (clamped into the triangle).
uint32_t bisection_piece_at(const Triangle& t, float piece_size, float b1, float b2);

}  // namespace bakegi::antiradiance
