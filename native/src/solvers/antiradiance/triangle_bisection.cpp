#include "solvers/antiradiance/triangle_bisection.h"

#include <algorithm>

#include "scene/triangle_geometry.h"

namespace bakegi::antiradiance {

namespace {

// The index i of the edge (corner i, corner i + 1) to cut, or -1 for a piece. Squared world
// lengths, the first longest on ties, so that every caller makes the same cuts.
int edge_to_cut(const Triangle& t, const glm::vec2 (&c)[3], float piece_size, int depth) {
  if (depth >= kMaxBisectionDepth) return -1;
  float longest = -1.0f;
  int edge = -1;
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 d = at_barycentrics(t.p, c[(i + 1) % 3]) - at_barycentrics(t.p, c[i]);
    const float length2 = glm::dot(d, d);
    if (length2 > longest) {
      longest = length2;
      edge = i;
    }
  }
  return longest > piece_size * piece_size ? edge : -1;
}

// The two halves of c cut at edge i: (P, M, R) and (M, Q, R) with P = c[i], Q = c[i + 1],
// R the opposite corner and M the midpoint of PQ (both counter-clockwise like c).
void halves(const glm::vec2 (&c)[3], int i, glm::vec2 (&first)[3], glm::vec2 (&second)[3]) {
  const glm::vec2 p = c[i], q = c[(i + 1) % 3], r = c[(i + 2) % 3];
  const glm::vec2 m = 0.5f * (p + q);
  first[0] = p, first[1] = m, first[2] = r;
  second[0] = m, second[1] = q, second[2] = r;
}

void descend(const Triangle& t, float piece_size, const glm::vec2 (&c)[3], uint32_t code,
             int depth, const std::function<void(const BisectionPiece&)>& piece) {
  const int edge = edge_to_cut(t, c, piece_size, depth);
  if (edge < 0) {
    BisectionPiece out;
    std::copy(c, c + 3, out.corners);
    out.code = code;
    out.depth = depth;
    piece(out);
    return;
  }
  glm::vec2 first[3], second[3];
  halves(c, edge, first, second);
  descend(t, piece_size, first, code << 1, depth + 1, piece);
  descend(t, piece_size, second, (code << 1) | 1u, depth + 1, piece);
}

uint64_t count(const Triangle& t, float piece_size, const glm::vec2 (&c)[3], int depth,
               uint64_t& budget) {
  if (budget == 0) return 0;
  const int edge = edge_to_cut(t, c, piece_size, depth);
  if (edge < 0) {
    --budget;
    return 1;
  }
  glm::vec2 first[3], second[3];
  halves(c, edge, first, second);
  const uint64_t a = count(t, piece_size, first, depth + 1, budget);
  return a + count(t, piece_size, second, depth + 1, budget);
}

constexpr glm::vec2 kRoot[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}};

float cross(glm::vec2 a, glm::vec2 b) { return a.x * b.y - a.y * b.x; }

}  // namespace

void bisect_triangle(const Triangle& t, float piece_size,
                     const std::function<void(const BisectionPiece&)>& piece) {
  descend(t, piece_size, kRoot, 1u, 0, piece);
}

uint64_t bisection_piece_count(const Triangle& t, float piece_size, uint64_t cap) {
  uint64_t budget = cap + 1;
  const uint64_t pieces = count(t, piece_size, kRoot, 0, budget);
  return budget == 0 ? cap + 1 : pieces;
}

uint32_t bisection_piece_at(const Triangle& t, float piece_size, float b1, float b2) {
  glm::vec2 u(std::clamp(b1, 0.0f, 1.0f), std::clamp(b2, 0.0f, 1.0f));
  if (u.x + u.y > 1.0f) u /= (u.x + u.y);
  glm::vec2 c[3] = {kRoot[0], kRoot[1], kRoot[2]};
  uint32_t code = 1u;
  for (int depth = 0;; ++depth) {
    const int edge = edge_to_cut(t, c, piece_size, depth);
    if (edge < 0) return code;
    glm::vec2 first[3], second[3];
    halves(c, edge, first, second);
    // The cut runs from M (first[1]) to R (first[2]); P (first[0]) is on the first half's side.
    const glm::vec2 m = first[1], r = first[2], p = first[0];
    const bool in_first = cross(r - m, u - m) * cross(r - m, p - m) >= 0.0f;
    std::copy(in_first ? first : second, (in_first ? first : second) + 3, c);
    code = (code << 1) | (in_first ? 0u : 1u);
  }
}

}  // namespace bakegi::antiradiance
