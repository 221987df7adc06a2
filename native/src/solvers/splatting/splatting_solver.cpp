#include "solvers/splatting/splatting_solver.h"

#include <atomic>

#include "lights/direct_light.h"
#include "scene/scene.h"
#include "solvers/splatting/near_field_gather.h"
#include "solvers/splatting/point_subsplats.h"
#include "solvers/splatting/reflective_shadow_map.h"
#include "solvers/splatting/splatting_settings.h"
#include "solvers/splatting/virtual_point_lights.h"
#include "solvers/splatting/vpl_visibility.h"
#include "util/job_context.h"
#include "util/report.h"

namespace bakegi {

namespace {

// The VPLs' light at bake points, through the point hierarchy (refinement "shared" or
// "illumination": the bake refines at geometric discontinuities either way) or at every
// point (refinement "none").
class SplattingField : public IndirectField {
 public:
  SplattingField(VirtualPointLights vpls, const SplattingSettings& settings, const Scene& scene,
                 const RayTracer& tracer, const DirectLight& direct)
      : vpls_(std::move(vpls)),
        settings_(settings),
        scene_(scene),
        tracer_(tracer),
        direct_(direct),
        bound_(settings.gather_rays > 0 ? geometry_bound(vpls_, settings.gather_radii) : 0.0f) {
    if (settings_.visibility_clusters > 0) {
      clusters_ = cluster_vpls(vpls_, settings_.visibility_clusters);
    }
  }

  void evaluate(const BakePoints& points, std::span<glm::vec3> out,
                JobContext& context) const override {
    std::atomic<uint64_t> rays{0};
    const PointLightFunction light = [&](const glm::vec3& position, const glm::vec3& normal,
                                         size_t point) {
      // The VPLs: clamped where the gather takes over, else bounded by their own surface.
      const auto range_light = [&](size_t begin, size_t end) {
        if (bound_ > 0.0f) return clamped_vpl_light(vpls_, position, normal, begin, end, bound_);
        return near_field_light(vpls_, position, normal, begin, end, settings_.near_field_split);
      };
      uint64_t traced = 0;
      // Bake points carry one normal: it stands for the geometric one too.
      glm::vec3 value = clusters_.count() > 0
                            ? visible_vpl_light(clusters_, tracer_, direct_.ray_epsilon(), position,
                                                normal, range_light, traced)
                            : range_light(0, vpls_.size());
      if (bound_ > 0.0f) {
        value += near_field_residual(scene_, tracer_, direct_, position, normal, bound_,
                                     settings_.gather_rays, settings_.seed, point, traced);
      }
      rays.fetch_add(traced, std::memory_order_relaxed);
      return value;
    };
    PointSubsplatOptions options;
    options.base_resolution = settings_.base_resolution;
    options.normal_threshold = settings_.discontinuity.normal_threshold;
    options.depth_threshold = settings_.discontinuity.depth_threshold;
    if (settings_.refinement == SubsplatRefinement::kNone) {
      options.normal_threshold = -1.0f;  // every cell splits: each point reads its own light
    }
    PointSubsplatStatistics statistics;
    splat_at_points(points.positions, points.normals, options, light, out, statistics, context);
    Report& report = context.report();
    report.add_count("rays", rays.load());
    report.add_count("splatting_vpls", vpls_.size());
    report.add_count("splatting_evaluations", statistics.evaluations);
    report.add_count("splatting_single_points", statistics.single_points);
  }

 private:
  VirtualPointLights vpls_;
  SplattingSettings settings_;
  VplClusters clusters_;
  const Scene& scene_;
  const RayTracer& tracer_;
  const DirectLight& direct_;
  float bound_;
};

}  // namespace

const std::vector<SettingSpec>& SplattingSolver::setting_specs() {
  return SplattingSettings::specs();
}

void SplattingSolver::check_settings(const Settings& settings) const {
  (void)SplattingSettings::from(settings);
}

std::unique_ptr<IndirectField> SplattingSolver::solve(const SolveInputs& inputs,
                                                      JobContext& context) {
  const SplattingSettings settings = SplattingSettings::from(inputs.settings);
  context.set_stage_text("reflective shadow maps");
  RsmOptions rsm = settings.rsm;
  rsm.ray_epsilon = inputs.direct.ray_epsilon();
  const std::vector<ReflectiveShadowMap> maps =
      render_reflective_shadow_maps(inputs.scene, inputs.tracer, rsm);
  uint64_t texels = 0;  // one ray each
  for (const ReflectiveShadowMap& map : maps) texels += map.texels.size();
  context.report().add_count("rays", texels);
  context.throw_if_cancelled();
  return std::make_unique<SplattingField>(
      select_vpls(maps, settings.vpl_count, settings.vpl_sampling), settings, inputs.scene,
      inputs.tracer, inputs.direct);
}

}  // namespace bakegi
