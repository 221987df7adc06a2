#include "lightmap/lightmap_seams.h"

#include <cmath>
#include <string>
#include <unordered_map>

#include "util/error.h"

namespace bakegi {

namespace {

// As in rasterize_texels: UV triangles under this many texels of area are skipped there.
constexpr double kMinPixelArea = 1e-9;

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Whether the rasterizer bakes the triangle (its tests, in the same order and precision).
bool rasterized(const LightmapTriangle& tri, uint32_t width, uint32_t height,
                glm::vec3& face_normal) {
  const glm::dvec3 cross =
      glm::cross(glm::dvec3(tri.p[1] - tri.p[0]), glm::dvec3(tri.p[2] - tri.p[0]));
  const double cross_length = glm::length(cross);
  if (!(cross_length > 0)) return false;
  face_normal = glm::vec3(cross / cross_length);
  glm::dvec2 t[3];
  for (int k = 0; k < 3; ++k) t[k] = glm::dvec2(tri.uv[k]) * glm::dvec2(width, height);
  const double twice_area =
      (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
  return std::abs(twice_area) > 2 * kMinPixelArea;
}

// The shading normal the rasterizer uses at a corner.
glm::vec3 corner_normal(const LightmapTriangle& tri, int corner, const glm::vec3& face_normal) {
  const float length = glm::length(tri.n[corner]);
  return finite(tri.n[corner]) && length > 1e-20f ? tri.n[corner] / length : face_normal;
}

// Up to two triangles on one edge, and where the edge's lower and higher vertex index sit
// among each one's corners.
struct EdgeUse {
  uint32_t count = 0;
  uint32_t triangle[2] = {0, 0};
  uint8_t low_corner[2] = {0, 0};
  uint8_t high_corner[2] = {0, 0};
};

}  // namespace

std::vector<LightmapSeam> find_lightmap_seams(std::span<const uint32_t> indices,
                                              const std::vector<LightmapTriangle>& triangles,
                                              uint32_t width, uint32_t height,
                                              const CancelFlag* cancel) {
  if (indices.size() != 3 * triangles.size()) {
    throw Error(BAKEGI_ERROR_INVALID_ARGUMENT,
                "find_lightmap_seams: " + std::to_string(indices.size()) + " indices for " +
                    std::to_string(triangles.size()) + " triangles");
  }
  const size_t count = triangles.size();
  std::vector<glm::vec3> face_normals(count);
  std::vector<uint8_t> baked(count);
  for (size_t t = 0; t < count; ++t) {
    if (t % 4096 == 0) throw_if_cancelled(cancel, "finding the lightmap seams");
    baked[t] = rasterized(triangles[t], width, height, face_normals[t]);
  }

  const auto key = [](uint32_t low, uint32_t high) { return uint64_t(low) << 32 | high; };
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(3 * count);
  for (size_t t = 0; t < count; ++t) {
    if (t % 4096 == 0) throw_if_cancelled(cancel, "finding the lightmap seams");
    if (!baked[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const int next = (k + 1) % 3;
      uint32_t low = indices[3 * t + k], high = indices[3 * t + next];
      int low_corner = k, high_corner = next;
      if (low > high) {
        std::swap(low, high);
        std::swap(low_corner, high_corner);
      }
      EdgeUse& use = edges[key(low, high)];
      if (use.count < 2) {
        use.triangle[use.count] = uint32_t(t);
        use.low_corner[use.count] = uint8_t(low_corner);
        use.high_corner[use.count] = uint8_t(high_corner);
      }
      ++use.count;
    }
  }

  std::vector<LightmapSeam> seams;
  const auto differ = [](const glm::vec2& a, const glm::vec2& b) {
    return glm::length(a - b) > kSeamUvEpsilon;
  };
  for (size_t t = 0; t < count; ++t) {
    if (!baked[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t i0 = indices[3 * t + k], i1 = indices[3 * t + (k + 1) % 3];
      const auto found = edges.find(key(std::min(i0, i1), std::max(i0, i1)));
      const EdgeUse& use = found->second;
      // Listed once, from its first triangle (a baked triangle has three distinct edges:
      // a repeated vertex index would give it zero area).
      if (use.count != 2 || use.triangle[0] != t) continue;
      const LightmapTriangle& ta = triangles[use.triangle[0]];
      const LightmapTriangle& tb = triangles[use.triangle[1]];
      const int a_corner[2] = {use.low_corner[0], use.high_corner[0]};
      const int b_corner[2] = {use.low_corner[1], use.high_corner[1]};
      LightmapSeam seam;
      bool same_normals = true;
      for (int e = 0; e < 2; ++e) {
        seam.a[e] = ta.uv[a_corner[e]];
        seam.b[e] = tb.uv[b_corner[e]];
        const glm::vec3 na = corner_normal(ta, a_corner[e], face_normals[use.triangle[0]]);
        const glm::vec3 nb = corner_normal(tb, b_corner[e], face_normals[use.triangle[1]]);
        same_normals = same_normals && glm::dot(na, nb) >= kSeamMinNormalCos;
      }
      if (!same_normals) continue;
      if (differ(seam.a[0], seam.b[0]) || differ(seam.a[1], seam.b[1])) seams.push_back(seam);
    }
  }
  return seams;
}

}  // namespace bakegi
