#include "solvers/splatting/min_max_mipmap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace bakegi {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Which of the mipmaps a test reads: only those are built.
struct Needs {
  bool range, derivative, components, curvature;
  explicit Needs(const DiscontinuityTest& t)
      : range(t.depth == DepthTest::kRange),
        derivative(t.depth == DepthTest::kDerivative),
        components(t.normal == NormalTest::kComponents),
        curvature(t.normal == NormalTest::kCurvature) {}
};

MipLevel make_level(uint32_t width, uint32_t height, uint32_t cell, const Needs& needs) {
  MipLevel l;
  l.width = width;
  l.height = height;
  l.cell = cell;
  const size_t n = size_t(width) * height;
  l.hits.assign(n, 0);
  if (needs.range) {
    l.depth_min.assign(n, kInf);
    l.depth_max.assign(n, -kInf);
  }
  if (needs.derivative) l.derivative_max.assign(n, 0.0f);
  if (needs.curvature) l.curvature_max.assign(n, 0.0f);
  if (needs.components) {
    l.normal_min.assign(n, glm::vec3(kInf));
    l.normal_max.assign(n, glm::vec3(-kInf));
  }
  l.representative.assign(n, MipLevel::kNone);
  return l;
}

// Pixels never split, so their own depth and normal ranges are not stored: the first
// reduction reads the G-buffer (a copy would cost a frame a few milliseconds).
MipLevel pixel_level(const EyeGBuffer& g, const Needs& needs) {
  Needs stored = needs;
  stored.range = stored.components = false;
  MipLevel l = make_level(g.width, g.height, 1, stored);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, g.height, 8), [&](const auto& rows) {
    for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
      for (uint32_t x = 0; x < g.width; ++x) {
        const size_t i = g.index(x, y);
        if (!g.hit[i]) continue;
        l.hits[i] = 1;
        l.representative[i] = uint32_t(i);
        if (!needs.derivative && !needs.curvature) continue;
        // Forward differences to the right and lower neighbours that are seen.
        float dzdx = 0.0f, dzdy = 0.0f, curvature = 0.0f;
        if (x + 1 < g.width && g.hit[i + 1]) {
          dzdx = (g.depth[i + 1] - g.depth[i]) / g.depth[i];
          curvature = std::max(curvature, glm::length(g.normal[i + 1] - g.normal[i]));
        }
        if (y + 1 < g.height && g.hit[i + g.width]) {
          dzdy = (g.depth[i + g.width] - g.depth[i]) / g.depth[i];
          curvature = std::max(curvature, glm::length(g.normal[i + g.width] - g.normal[i]));
        }
        if (needs.derivative) l.derivative_max[i] = std::sqrt(dzdx * dzdx + dzdy * dzdy);
        if (needs.curvature) l.curvature_max[i] = curvature;
      }
    }
  });
  return l;
}

// `gbuffer`: the pixels' depth and normal when `fine` is the pixel level, else null.
MipLevel reduce(const MipLevel& fine, const EyeGBuffer& pixels, const Needs& needs,
                const EyeGBuffer* gbuffer) {
  const uint32_t image_width = pixels.width;
  MipLevel l = make_level((fine.width + 1) / 2, (fine.height + 1) / 2, fine.cell * 2, needs);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, l.height, 8), [&](const auto& rows) {
    for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
      for (uint32_t x = 0; x < l.width; ++x) {
        const size_t o = l.index(x, y);
        // The representative: the pixel at the texel's centre if seen, else the children's
        // representative nearest that centre (an off-centre sample shifts the light by up to
        // half a texel, which the upsampling cannot undo; the children's representatives
        // alone drift from it, 1.5 pixels at 8-pixel texels, a 1.7% bias on the office's
        // gradients).
        const float centre_x = (float(x) + 0.5f) * float(l.cell) - 0.5f;
        const float centre_y = (float(y) + 0.5f) * float(l.cell) - 0.5f;
        const uint32_t middle_x = x * l.cell + l.cell / 2, middle_y = y * l.cell + l.cell / 2;
        const bool middle_seen = middle_x < pixels.width && middle_y < pixels.height &&
                                 pixels.hit[pixels.index(middle_x, middle_y)];
        if (middle_seen) l.representative[o] = uint32_t(pixels.index(middle_x, middle_y));
        float nearest = middle_seen ? 0.0f : 1e30f;
        for (uint32_t c = 0; c < 4; ++c) {
          const uint32_t fx = 2 * x + (c & 1), fy = 2 * y + (c >> 1);
          if (fx >= fine.width || fy >= fine.height) continue;
          const size_t i = fine.index(fx, fy);
          if (fine.hits[i] == 0) continue;
          l.hits[o] += fine.hits[i];
          if (needs.range) {
            l.depth_min[o] =
                std::min(l.depth_min[o], gbuffer ? gbuffer->depth[i] : fine.depth_min[i]);
            l.depth_max[o] =
                std::max(l.depth_max[o], gbuffer ? gbuffer->depth[i] : fine.depth_max[i]);
          }
          if (needs.derivative) {
            l.derivative_max[o] = std::max(l.derivative_max[o], fine.derivative_max[i]);
          }
          if (needs.curvature) {
            l.curvature_max[o] = std::max(l.curvature_max[o], fine.curvature_max[i]);
          }
          if (needs.components) {
            l.normal_min[o] =
                glm::min(l.normal_min[o], gbuffer ? gbuffer->normal[i] : fine.normal_min[i]);
            l.normal_max[o] =
                glm::max(l.normal_max[o], gbuffer ? gbuffer->normal[i] : fine.normal_max[i]);
          }
          const uint32_t r = fine.representative[i];
          const float dx = float(r % image_width) - centre_x,
                      dy = float(r / image_width) - centre_y;
          if (dx * dx + dy * dy < nearest) nearest = dx * dx + dy * dy, l.representative[o] = r;
        }
      }
    }
  });
  return l;
}

}  // namespace

uint32_t coarsest_level_for(uint32_t width, uint32_t height, uint32_t base_resolution) {
  const uint32_t larger = std::max(width, height);
  uint32_t k = 0;
  while ((larger >> k) > std::max(1u, base_resolution)) ++k;
  return k;
}

MinMaxMipmap::MinMaxMipmap(const EyeGBuffer& gbuffer, uint32_t coarsest,
                           const DiscontinuityTest& test)
    : image_width_(gbuffer.width), image_height_(gbuffer.height) {
  const Needs needs(test);
  levels_.push_back(pixel_level(gbuffer, needs));
  for (uint32_t k = 1; k <= coarsest; ++k) {
    levels_.push_back(reduce(levels_.back(), gbuffer, needs, k == 1 ? &gbuffer : nullptr));
  }
}

SurfacePoint MinMaxMipmap::point(const EyeGBuffer& g, uint32_t k, uint32_t x, uint32_t y,
                                 const DiscontinuityTest& test) const {
  const MipLevel& l = levels_[k];
  const uint32_t r = l.representative[l.index(x, y)];
  const SurfacePoint own{g.position[r], g.normal[r], g.geometric[r]};  // (shading, geometric)
  if (k == 0) return own;
  const uint32_t x1 = x * l.cell + l.cell / 2, y1 = y * l.cell + l.cell / 2;
  if (x1 >= g.width || y1 >= g.height) return own;
  const size_t middle[4] = {g.index(x1 - 1, y1 - 1), g.index(x1, y1 - 1), g.index(x1 - 1, y1),
                            g.index(x1, y1)};
  float depth_lo = kInf, depth_hi = 0.0f;
  glm::vec3 normal_lo(kInf), normal_hi(-kInf);
  SurfacePoint mean{glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
  for (const size_t i : middle) {
    if (!g.hit[i]) return own;
    depth_lo = std::min(depth_lo, g.depth[i]);
    depth_hi = std::max(depth_hi, g.depth[i]);
    normal_lo = glm::min(normal_lo, g.normal[i]);
    normal_hi = glm::max(normal_hi, g.normal[i]);
    mean.position += 0.25f * g.position[i];
    mean.shading_normal += g.normal[i];
    mean.geometric_normal += g.geometric[i];
  }
  const glm::vec3 range = normal_hi - normal_lo;
  if (depth_hi - depth_lo > test.depth_threshold * depth_lo ||
      std::max(range.x, std::max(range.y, range.z)) > test.normal_threshold ||
      glm::dot(mean.shading_normal, mean.shading_normal) < 1e-12f ||
      glm::dot(mean.geometric_normal, mean.geometric_normal) < 1e-12f) {
    return own;
  }
  mean.shading_normal = glm::normalize(mean.shading_normal);
  mean.geometric_normal = glm::normalize(mean.geometric_normal);
  return mean;
}

bool MinMaxMipmap::discontinuous(uint32_t k, uint32_t x, uint32_t y,
                                 const DiscontinuityTest& test) const {
  const MipLevel& l = levels_[k];
  if (x >= l.width || y >= l.height) return false;
  const size_t i = l.index(x, y);
  if (l.hits[i] == 0) return false;
  const uint32_t w = std::min(l.cell, image_width_ - x * l.cell);
  const uint32_t h = std::min(l.cell, image_height_ - y * l.cell);
  if (l.hits[i] < w * h) return true;  // surface and background share the texel
  if (k == 0) return false;
  if (test.depth == DepthTest::kRange) {
    if (l.depth_max[i] - l.depth_min[i] > test.depth_threshold * l.depth_min[i]) return true;
  } else if (l.derivative_max[i] > test.depth_threshold) {
    return true;
  }
  if (test.normal == NormalTest::kComponents) {
    const glm::vec3 range = l.normal_max[i] - l.normal_min[i];
    return std::max(range.x, std::max(range.y, range.z)) > test.normal_threshold;
  }
  return l.curvature_max[i] > test.normal_threshold;
}

bool MinMaxMipmap::discontinuous_with_neighbours(uint32_t k, uint32_t x, uint32_t y,
                                                 const DiscontinuityTest& test) const {
  const MipLevel& l = levels_[k];
  float depth_lo = kInf, depth_hi = -kInf, derivative = 0.0f, curvature = 0.0f;
  glm::vec3 normal_lo(kInf), normal_hi(-kInf);
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = int(x) + dx, ny = int(y) + dy;
      if (nx < 0 || ny < 0 || nx >= int(l.width) || ny >= int(l.height)) continue;
      const size_t i = l.index(uint32_t(nx), uint32_t(ny));
      const uint32_t w = std::min(l.cell, image_width_ - uint32_t(nx) * l.cell);
      const uint32_t h = std::min(l.cell, image_height_ - uint32_t(ny) * l.cell);
      if (l.hits[i] < w * h) return true;  // background beside or inside
      if (test.depth == DepthTest::kRange) {
        depth_lo = std::min(depth_lo, l.depth_min[i]);
        depth_hi = std::max(depth_hi, l.depth_max[i]);
      } else {
        derivative = std::max(derivative, l.derivative_max[i]);
      }
      if (test.normal == NormalTest::kComponents) {
        normal_lo = glm::min(normal_lo, l.normal_min[i]);
        normal_hi = glm::max(normal_hi, l.normal_max[i]);
      } else {
        curvature = std::max(curvature, l.curvature_max[i]);
      }
    }
  }
  if (test.depth == DepthTest::kRange ? depth_hi - depth_lo > test.depth_threshold * depth_lo
                                      : derivative > test.depth_threshold) {
    return true;
  }
  if (test.normal == NormalTest::kComponents) {
    const glm::vec3 range = normal_hi - normal_lo;
    return std::max(range.x, std::max(range.y, range.z)) > test.normal_threshold;
  }
  return curvature > test.normal_threshold;
}

bool MinMaxMipmap::refines(uint32_t k, uint32_t x, uint32_t y,
                           const DiscontinuityTest& test) const {
  const MipLevel& l = levels_[k];
  if (x >= l.width || y >= l.height || l.hits[l.index(x, y)] == 0) return false;
  if (test.neighbours == NeighbourTest::kAll) {
    return discontinuous_with_neighbours(k, x, y, test);
  }
  if (discontinuous(k, x, y, test)) return true;
  if (test.neighbours == NeighbourTest::kNone) return false;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;
      if (dx == 0 || dy == 0) continue;  // the diagonal neighbours only
      const int nx = int(x) + dx, ny = int(y) + dy;
      if (nx < 0 || ny < 0) continue;
      if (discontinuous(k, uint32_t(nx), uint32_t(ny), test)) return true;
    }
  }
  return false;
}

}  // namespace bakegi
