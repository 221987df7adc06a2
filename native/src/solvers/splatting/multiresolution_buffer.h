// The multiresolution illumination buffer (Nichols & Wyman 2009, §3.4, §3.5): one image per
// level, each subsplat's indirect light written as one texel of its level (equation 2 summed
// over the VPLs), then upsampled coarsest to finest into one image.
//
// Upsampling (§3.5): coarsest to finest, each texel that holds light (rendered at its level,
// or brought up from the coarser ones) hands it to its four children by bilinear
// interpolation among the neighbours of its level that also hold light; texels without
// light stay empty, so light is neither pulled from nor spread into the regions refined
// further, and never crosses the discontinuities that made them. (The paper's 3x3 weights
// are read as this interpolation to the next level: applied as a blur of every level's own
// samples they would flatten peaks and bias edges, 4.8% against full resolution on the
// Cornell box instead of the 2% the issue asks for.) Nearest and naive bilinear upsampling
// are kept to show the artifacts of their Fig. 7.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/splatting/subsplat_refinement.h"

namespace bakegi {

enum class Upsampling { kInterpolated, kNearest, kBilinear };

class MultiresolutionBuffer {
 public:
  MultiresolutionBuffer(uint32_t width, uint32_t height, uint32_t levels);

  // Adds light at a subsplat's texel (thread-safe only between distinct texels).
  void add(const Subsplat& s, const glm::vec3& value);
  // Adds another buffer of the same size (the per-thread buffers of §3.3.1's variant).
  void add(const MultiresolutionBuffer& other);

  // The combined full-resolution image (row order); pixels no subsplat covers are 0. The
  // interpolated upsampling works in the buffer's own levels, which it leaves changed.
  std::vector<glm::vec3> upsample(Upsampling mode);
  // The same into `image`, whose memory is reused (a frame's 3.7 MB at 640x480).
  void upsample(Upsampling mode, std::vector<glm::vec3>& image);
  // Empties every texel and keeps the memory, for the next frame (a fresh buffer of 640x480
  // costs a frame 2 ms of page faults and zeroing; this clears one byte per texel).
  void clear();

  uint32_t levels() const { return uint32_t(levels_.size()); }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

 private:
  struct Level {
    uint32_t width = 0, height = 0;
    std::vector<glm::vec3> light;  // meaningful only where filled
    std::vector<uint8_t> filled;
    glm::vec3 at(size_t i) const { return filled[i] ? light[i] : glm::vec3(0.0f); }
  };
  void upsample_interpolated(std::vector<glm::vec3>& image);
  // Σ over levels of sample(level, k, x, y) at every pixel (the two Fig. 7 combinations).
  template <typename Sample>
  void sum_levels(Sample&& sample, std::vector<glm::vec3>& image) const;
  void upsample_nearest(std::vector<glm::vec3>& image) const;
  void upsample_bilinear(std::vector<glm::vec3>& image) const;

  uint32_t width_, height_;
  std::vector<Level> levels_;
};

// Renders every subsplat of `set` into `buffer`: the light at the subsplat's point
// (MinMaxMipmap::point), in parallel.
void render_subsplats(const SubsplatSet& set, const MinMaxMipmap& mipmap, const EyeGBuffer& gbuffer,
                      const DiscontinuityTest& test, const SurfaceLight& light,
                      MultiresolutionBuffer& buffer);

}  // namespace bakegi
