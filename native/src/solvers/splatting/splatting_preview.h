// One frame of the interactive preview (Nichols & Wyman 2009, §3, steps 1-7): reflective
// shadow maps and VPLs from the lights, the eye's G-buffer and direct light, the splatted
// indirect light, and their sum. The scene's geometry is built once (its BVH too); lights
// change between frames without re-export, and the G-buffer is kept while the camera and
// image size stay.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "solvers/splatting/eye_gbuffer.h"
#include "solvers/splatting/splatting_indirect.h"
#include "solvers/splatting/splatting_settings.h"

namespace bakegi {

class RayTracer;

struct PreviewStatistics {
  SplatStatistics splat;
  double seconds_gbuffer = 0, seconds_direct = 0, seconds_rsm = 0, seconds_vpls = 0;
  double seconds_glossy = 0;
  uint64_t glossy_pixels = 0;
  double seconds_total = 0;
  bool gbuffer_reused = false;
  uint64_t vpls = 0, rsm_texels = 0;
};

struct PreviewFrame {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> direct;    // E_direct / pi per pixel
  std::vector<glm::vec3> indirect;  // E_indirect / pi per pixel
  std::vector<glm::vec3> glossy;    // radiance the gathered glossy lobes reflect
  // radiance: emission + albedo (direct + indirect) + glossy, the albedo with the folded
  // lobes (glossy_receivers.h)
  std::vector<glm::vec3> combined;
  std::vector<uint8_t> seen;  // 1 where a surface was seen (0: the world shows)
  PreviewStatistics statistics;
};

class SplattingPreview {
 public:
  // Builds the scene and its BVH (throws Error on a bad scene).
  explicit SplattingPreview(const SceneDescription& description);
  ~SplattingPreview();

  // Replaces the lights and the world's radiance; geometry and materials stay.
  void set_lights(const std::vector<Light>& lights, const glm::vec3& world_radiance);
  // The frame stays valid until the next call (its memory is reused).
  const PreviewFrame& render(const PreviewCamera& camera, uint32_t width, uint32_t height,
                             const SplattingSettings& settings);

  const Scene& scene() const { return *scene_; }

 private:
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<RayTracer> tracer_;
  EyeGBuffer gbuffer_;
  PreviewCamera gbuffer_camera_;
  bool gbuffer_valid_ = false;
  SplatFrameCache splat_cache_;  // follows the G-buffer
  PreviewFrame frame_;
  std::vector<glm::vec3> albedo_;  // the G-buffer's, folded glossy lobes added
};

}  // namespace bakegi
