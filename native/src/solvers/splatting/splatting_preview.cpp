#include "solvers/splatting/splatting_preview.h"

#include <chrono>

#include "lights/direct_light.h"
#include "scene/ray_tracer.h"
#include "scene/scene_validation.h"
#include "solvers/splatting/glossy_receivers.h"
#include "solvers/splatting/reflective_shadow_map.h"
#include "solvers/splatting/virtual_point_lights.h"

namespace bakegi {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

SplattingPreview::SplattingPreview(const SceneDescription& description)
    : scene_(std::make_unique<Scene>(build_scene(description))),
      tracer_(std::make_unique<RayTracer>(*scene_)) {}

SplattingPreview::~SplattingPreview() = default;

void SplattingPreview::set_lights(const std::vector<Light>& lights,
                                  const glm::vec3& world_radiance) {
  scene_->description.lights = lights;
  scene_->description.world_radiance = world_radiance;
}

const PreviewFrame& SplattingPreview::render(const PreviewCamera& camera, uint32_t width,
                                             uint32_t height, const SplattingSettings& settings) {
  const auto frame_start = std::chrono::steady_clock::now();
  PreviewFrame& frame = frame_;  // its memory serves the next frame too
  frame.statistics = PreviewStatistics();
  frame.width = width;
  frame.height = height;
  PreviewStatistics& stats = frame.statistics;

  auto start = std::chrono::steady_clock::now();
  if (gbuffer_valid_ && gbuffer_camera_ == camera && gbuffer_.width == width &&
      gbuffer_.height == height) {
    stats.gbuffer_reused = true;
  } else {
    gbuffer_ = trace_eye_gbuffer(*scene_, *tracer_, camera, width, height);
    splat_cache_.reset();
    gbuffer_camera_ = camera;
    gbuffer_valid_ = true;
  }
  stats.seconds_gbuffer = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const DirectLight direct(*scene_, *tracer_);
  frame.direct = eye_direct_light(gbuffer_, direct, settings.direct_samples, settings.seed);
  stats.seconds_direct = seconds_since(start);

  start = std::chrono::steady_clock::now();
  RsmOptions rsm = settings.rsm;
  rsm.ray_epsilon = direct.ray_epsilon();
  const std::vector<ReflectiveShadowMap> maps =
      render_reflective_shadow_maps(*scene_, *tracer_, rsm);
  for (const ReflectiveShadowMap& m : maps) stats.rsm_texels += m.texels.size();
  stats.seconds_rsm = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const VirtualPointLights vpls = select_vpls(maps, settings.vpl_count, settings.vpl_sampling);
  stats.vpls = vpls.size();
  stats.seconds_vpls = seconds_since(start);

  splat_indirect(gbuffer_, vpls, settings, stats.splat, frame.indirect, tracer_.get(),
                 direct.ray_epsilon(), &splat_cache_);

  start = std::chrono::steady_clock::now();
  stats.glossy_pixels =
      glossy_reflection(gbuffer_, direct, vpls, settings.direct_samples, settings.seed,
                        settings.glossy_fold_exponent, frame.glossy);
  folded_albedo(gbuffer_, settings.glossy_fold_exponent, albedo_);
  stats.seconds_glossy = seconds_since(start);

  const size_t n = gbuffer_.size();
  frame.combined.assign(n, scene_->description.world_radiance);
  frame.seen = gbuffer_.hit;
  for (size_t i = 0; i < n; ++i) {
    if (!gbuffer_.hit[i]) continue;
    frame.combined[i] =
        gbuffer_.emission[i] + albedo_[i] * (frame.direct[i] + frame.indirect[i]) + frame.glossy[i];
  }
  stats.seconds_total = seconds_since(frame_start);
  return frame;
}

}  // namespace bakegi
