// Steps 3 to 6 of Nichols & Wyman 2009 (§3.2-3.5) for one G-buffer and one set of VPLs:
// min-max mipmap, subsplat refinement, rendering into the multiresolution buffer and
// upsampling, with each step's time and the subsplat counts per level (their Tables 1-2).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "solvers/splatting/eye_gbuffer.h"
#include "solvers/splatting/min_max_mipmap.h"
#include "solvers/splatting/multiresolution_buffer.h"
#include "solvers/splatting/splatting_settings.h"

namespace bakegi {

class RayTracer;

struct SplatStatistics {
  double seconds_mipmap = 0, seconds_refine = 0, seconds_render = 0, seconds_upsample = 0;
  std::vector<uint64_t> subsplats_per_level;  // index = level (texels of 2^level pixels)
  uint64_t subsplats = 0;
  uint32_t coarsest_level = 0, finest_level = 0;
  bool mipmap_reused = false;  // taken from a SplatFrameCache
  // Per pixel, the level of the subsplat that covers it (255: none), for the refinement
  // pictures (shared and full-resolution splatting; empty for the per-VPL variant).
  std::vector<uint8_t> pixel_levels;
};

// What a frame leaves for the next while the G-buffer stays (the preview while only lights
// move): the min-max mipmap, which depends on the G-buffer alone (rebuilding it is a tenth
// of a relit frame), and the multiresolution buffer's memory (allocating it anew, 2 ms of
// page faults and zeroing at 640x480). Whoever changes the G-buffer must reset it.
struct SplatFrameCache {
  std::unique_ptr<MinMaxMipmap> mipmap;
  uint32_t mipmap_coarsest = 0;
  DepthTest mipmap_depth = DepthTest::kRange;  // the mipmaps a test reads depend on these
  NormalTest mipmap_normal = NormalTest::kComponents;
  std::unique_ptr<MultiresolutionBuffer> buffer;
  void reset() {
    mipmap.reset();
    buffer.reset();
  }
};

// Indirect irradiance / pi at every pixel of `gbuffer` (0 where nothing is seen), into
// `image` (resized; its memory is reused). With
// `tracer` and settings.visibility_clusters > 0, each subsplat's light passes the clustered
// shadow rays of vpl_visibility.h (the §3.3.1 variant ignores them).
void splat_indirect(const EyeGBuffer& gbuffer, const VirtualPointLights& vpls,
                    const SplattingSettings& settings, SplatStatistics& statistics,
                    std::vector<glm::vec3>& image, const RayTracer* tracer = nullptr,
                    float ray_epsilon = 0.0f, SplatFrameCache* cache = nullptr);

}  // namespace bakegi
