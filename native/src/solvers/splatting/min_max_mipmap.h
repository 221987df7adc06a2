// Min-max mipmaps of the eye's G-buffer (Nichols & Wyman 2009, §2.2, §3.2, §4.1): each level
// halves the resolution and keeps, per texel, the smallest and largest value of its children
// instead of their mean, so one lookup tells whether a texel's screen area holds a depth or
// normal discontinuity. All four variants the paper compares are built:
//   depth range       min and max of linear depth (§3.2.1), relative: (max - min) / min;
//   depth derivative  max of |grad z| / z per pixel, a max-mipmap (§3.2.1);
//   normal components min and max of each normal component (§3.2.2);
//   curvature         max of 2 sin(angle / 2) = |n1 - n2| between neighbouring pixels,
//                     their equation 1 (§3.2.2).
// Depth is relative (a fraction of the nearer depth) so that one threshold serves scenes of
// any size. A texel whose area holds both surface and background counts as discontinuous.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "lights/surface_point.h"
#include "solvers/splatting/eye_gbuffer.h"

namespace bakegi {

enum class DepthTest { kRange, kDerivative };
enum class NormalTest { kComponents, kCurvature };
// Which neighbours of a subsplat also make it refine (§5.2): none; the four diagonal ones
// whose own texel is discontinuous (the paper's fix for diagonal artifacts); all eight,
// tested together with the texel as one area (its fix for edges that lie on a texel
// boundary, which no single texel's min and max can see; up to 40% more subsplats).
enum class NeighbourTest { kNone, kDiagonal, kAll };

struct DiscontinuityTest {
  DepthTest depth = DepthTest::kRange;
  NormalTest normal = NormalTest::kComponents;
  NeighbourTest neighbours = NeighbourTest::kDiagonal;
  float depth_threshold = 0.03f;  // relative depth range, or |grad z| / z per pixel
  float normal_threshold = 0.5f;  // component range [0, 2], or curvature [0, 2]
};

struct MipLevel {
  uint32_t width = 0, height = 0;
  uint32_t cell = 1;           // pixels per side of a texel
  std::vector<uint32_t> hits;  // seen pixels in the texel's area
  // Empty where the test does not read them, and depth and normal ranges at the pixel level
  // (pixels never split; the G-buffer holds their values).
  std::vector<float> depth_min, depth_max, derivative_max, curvature_max;
  std::vector<glm::vec3> normal_min, normal_max;
  // A seen pixel near the texel's centre: where a subsplat at this texel reads the G-buffer
  // (kNone where no pixel is seen).
  std::vector<uint32_t> representative;
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  size_t index(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
};

// The indirect light where a subsplat reads the surface (thread-safe).
using SurfaceLight = std::function<glm::vec3(const SurfacePoint&)>;

class MinMaxMipmap {
 public:
  // Levels 0 (pixels) to `coarsest` (texels of 2^coarsest pixels), holding the mipmaps
  // `test` reads (the others stay empty).
  MinMaxMipmap(const EyeGBuffer& gbuffer, uint32_t coarsest, const DiscontinuityTest& test);

  uint32_t levels() const { return uint32_t(levels_.size()); }
  const MipLevel& level(uint32_t k) const { return levels_[k]; }
  // Whether the texel's own area holds a discontinuity under `test`.
  bool discontinuous(uint32_t k, uint32_t x, uint32_t y, const DiscontinuityTest& test) const;
  // Whether a subsplat at (k, x, y) refines: its own texel or, per test.neighbours, a
  // neighbouring one is discontinuous.
  bool refines(uint32_t k, uint32_t x, uint32_t y, const DiscontinuityTest& test) const;
  // Where the subsplat at (k, x, y) reads the surface: its texel's centre, which the
  // upsampling takes its light to stand for. A texel of 2^k pixels has its centre between
  // its four middle pixels: their mean position and normals where all four are seen and
  // continuous under `test` (on a plane, the surface at the centre exactly); else the
  // representative pixel. Any pixel would be off by at least half a pixel: a bias of the
  // gradient times that everywhere (0.6% on the office's lit panel).
  SurfacePoint point(const EyeGBuffer& gbuffer, uint32_t k, uint32_t x, uint32_t y,
                     const DiscontinuityTest& test) const;

 private:
  // The texel and its eight neighbours as one area (NeighbourTest::kAll).
  bool discontinuous_with_neighbours(uint32_t k, uint32_t x, uint32_t y,
                                     const DiscontinuityTest& test) const;

  std::vector<MipLevel> levels_;
  uint32_t image_width_, image_height_;
};

// The coarsest level whose texels number about `base_resolution` along the image's larger
// side (the paper starts from 16^2 subsplats).
uint32_t coarsest_level_for(uint32_t width, uint32_t height, uint32_t base_resolution);

}  // namespace bakegi
