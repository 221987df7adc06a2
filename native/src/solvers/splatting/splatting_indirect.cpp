#include "solvers/splatting/splatting_indirect.h"

#include <algorithm>
#include <chrono>

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include "solvers/splatting/subsplat_refinement.h"
#include "solvers/splatting/virtual_point_lights.h"
#include "solvers/splatting/vpl_visibility.h"
#include "util/luminance.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// §3.3.1: each VPL refines its own subsplats and renders them into a per-thread buffer.
MultiresolutionBuffer render_illumination_refined(const MinMaxMipmap& mipmap, const EyeGBuffer& g,
                                                  const VirtualPointLights& vpls, uint32_t coarsest,
                                                  uint32_t finest, float threshold, float extent,
                                                  std::vector<uint64_t>& per_level) {
  tbb::combinable<MultiresolutionBuffer> buffers(
      [&] { return MultiresolutionBuffer(g.width, g.height, mipmap.levels()); });
  tbb::combinable<std::vector<uint64_t>> counts(
      [&] { return std::vector<uint64_t>(mipmap.levels(), 0); });
  tbb::parallel_for(size_t(0), vpls.size(), [&](size_t v) {
    MultiresolutionBuffer& buffer = buffers.local();
    std::vector<uint64_t>& count = counts.local();
    // The floor of the relative test: this VPL's light at the scene's own size, so that
    // faint far regions do not split on relative noise.
    const float floor = float(max_component(vpls.fluxes[v])) / (kPi * kPi * extent * extent);
    illumination_refined_subsplats(mipmap, g, vpls, v, coarsest, finest, threshold, floor,
                                   [&](const Subsplat& s, const glm::vec3& value) {
                                     buffer.add(s, value);
                                     ++count[s.level];
                                   });
  });
  MultiresolutionBuffer total(g.width, g.height, mipmap.levels());
  buffers.combine_each([&](const MultiresolutionBuffer& b) { total.add(b); });
  per_level.assign(mipmap.levels(), 0);
  counts.combine_each([&](const std::vector<uint64_t>& c) {
    for (size_t k = 0; k < c.size(); ++k) per_level[k] += c[k];
  });
  return total;
}

float scene_extent_of(const EyeGBuffer& g) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (size_t i = 0; i < g.size(); ++i) {
    if (!g.hit[i]) continue;
    lo = glm::min(lo, g.position[i]);
    hi = glm::max(hi, g.position[i]);
  }
  const float e = glm::length(hi - lo);
  return e > 0.0f ? e : 1.0f;
}

// Steps 3-6 with the multiresolution buffer (refinement shared, by light, or per VPL).
void splat_multiresolution(const EyeGBuffer& gbuffer, const VirtualPointLights& vpls,
                           const SplattingSettings& settings, const SurfaceLight& surface_light,
                           SplatStatistics& statistics, SplatFrameCache& cache,
                           std::vector<glm::vec3>& image) {
  auto start = std::chrono::steady_clock::now();
  const uint32_t coarsest =
      coarsest_level_for(gbuffer.width, gbuffer.height, settings.base_resolution);
  const uint32_t finest = settings.max_resolution == 0
                              ? 0
                              : std::min(coarsest, coarsest_level_for(gbuffer.width, gbuffer.height,
                                                                      settings.max_resolution));
  statistics.coarsest_level = coarsest;
  statistics.finest_level = finest;
  const DiscontinuityTest& test = settings.discontinuity;
  statistics.mipmap_reused = cache.mipmap && cache.mipmap_coarsest == coarsest &&
                             cache.mipmap_depth == test.depth && cache.mipmap_normal == test.normal;
  if (!statistics.mipmap_reused) {
    cache.mipmap = std::make_unique<MinMaxMipmap>(gbuffer, coarsest, test);
    cache.mipmap_coarsest = coarsest;
    cache.mipmap_depth = test.depth;
    cache.mipmap_normal = test.normal;
  }
  const MinMaxMipmap& mipmap = *cache.mipmap;
  statistics.seconds_mipmap = seconds_since(start);

  start = std::chrono::steady_clock::now();
  if (cache.buffer && cache.buffer->width() == gbuffer.width &&
      cache.buffer->height() == gbuffer.height && cache.buffer->levels() == mipmap.levels()) {
    cache.buffer->clear();
  } else {
    cache.buffer =
        std::make_unique<MultiresolutionBuffer>(gbuffer.width, gbuffer.height, mipmap.levels());
  }
  MultiresolutionBuffer& buffer = *cache.buffer;
  const bool per_vpl = settings.refinement == SubsplatRefinement::kIllumination;
  if (per_vpl) {
    buffer = render_illumination_refined(mipmap, gbuffer, vpls, coarsest, finest,
                                         settings.illumination_threshold, scene_extent_of(gbuffer),
                                         statistics.subsplats_per_level);
    statistics.seconds_render = seconds_since(start);
  } else {
    SubsplatSet set;
    if (settings.light_threshold > 0.0f) {
      // Refinement and rendering at once: the light decides the last splits.
      std::vector<glm::vec3> values;
      set = refine_subsplats_by_light(mipmap, gbuffer, coarsest, finest, settings.discontinuity,
                                      settings.light_threshold, surface_light, values);
      // Each subsplat has a texel of its own, so threads never write the same one.
      tbb::parallel_for(tbb::blocked_range<size_t>(0, set.subsplats.size(), 1024),
                        [&](const auto& r) {
                          for (size_t i = r.begin(); i != r.end(); ++i) {
                            buffer.add(set.subsplats[i], values[i]);
                          }
                        });
      statistics.seconds_render = seconds_since(start);
    } else {
      set = refine_subsplats(mipmap, coarsest, finest, settings.discontinuity);
      statistics.seconds_refine = seconds_since(start);
      start = std::chrono::steady_clock::now();
      render_subsplats(set, mipmap, gbuffer, settings.discontinuity, surface_light, buffer);
      statistics.seconds_render = seconds_since(start);
    }
    statistics.subsplats_per_level = set.per_level;
    if (settings.record_pixel_levels) {
      statistics.pixel_levels.assign(gbuffer.size(), 255);
      for (const Subsplat& sub : set.subsplats) {
        const uint32_t cell = 1u << sub.level;
        for (uint32_t y = sub.y * cell; y < std::min(gbuffer.height, (sub.y + 1) * cell); ++y) {
          for (uint32_t x = sub.x * cell; x < std::min(gbuffer.width, (sub.x + 1) * cell); ++x) {
            statistics.pixel_levels[gbuffer.index(x, y)] = uint8_t(sub.level);
          }
        }
      }
    }
  }

  start = std::chrono::steady_clock::now();
  // The per-VPL variant's subsplats differ between VPLs, so a texel's neighbours hold other
  // VPLs' light: the interpolation, which averages neighbours that hold light, would mix
  // them; each VPL's subsplats are whole pieces of its light, which nearest upsampling sums.
  buffer.upsample(per_vpl ? Upsampling::kNearest : settings.upsampling, image);
  statistics.seconds_upsample = seconds_since(start);
}

}  // namespace

void splat_indirect(const EyeGBuffer& gbuffer, const VirtualPointLights& vpls,
                    const SplattingSettings& settings, SplatStatistics& statistics,
                    std::vector<glm::vec3>& image, const RayTracer* tracer, float ray_epsilon,
                    SplatFrameCache* cache) {
  // The light at a pixel: through the clustered shadow rays, or the paper's VPL light.
  VirtualPointLights clustered;
  VplClusters clusters;
  if (tracer && settings.visibility_clusters > 0) {
    clustered = vpls;
    clusters = cluster_vpls(clustered, settings.visibility_clusters);
  }
  const SurfaceLight surface_light = [&](const SurfacePoint& p) {
    if (clusters.count() > 0) {
      uint64_t rays = 0;  // a frame reports times, not rays
      return visible_vpl_light(
          clusters, *tracer, ray_epsilon, p.position, p.geometric_normal,
          [&](size_t begin, size_t end) {
            return near_field_light(clustered, p.position, p.shading_normal, begin, end,
                                    settings.near_field_split);
          },
          rays);
    }
    if (settings.near_field_split > 0.0f) {
      return near_field_light(vpls, p.position, p.shading_normal, 0, vpls.size(),
                              settings.near_field_split);
    }
    return vpl_irradiance_over_pi(vpls, p.position, p.shading_normal);
  };

  if (settings.refinement == SubsplatRefinement::kNone) {
    // Full-resolution splatting, the baseline: every seen pixel gathers, nothing else.
    const auto start = std::chrono::steady_clock::now();
    image.assign(gbuffer.size(), glm::vec3(0.0f));
    tbb::parallel_for(tbb::blocked_range<size_t>(0, gbuffer.size(), 256), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        if (gbuffer.hit[i]) {
          image[i] = surface_light({gbuffer.position[i], gbuffer.normal[i], gbuffer.geometric[i]});
        }
      }
    });
    statistics.seconds_render = seconds_since(start);
    const uint64_t seen = uint64_t(std::count(gbuffer.hit.begin(), gbuffer.hit.end(), 1));
    statistics.subsplats_per_level = {seen};
    if (settings.record_pixel_levels) {
      statistics.pixel_levels.assign(gbuffer.size(), 255);
      for (size_t i = 0; i < gbuffer.size(); ++i) {
        if (gbuffer.hit[i]) statistics.pixel_levels[i] = 0;
      }
    }
  } else {
    SplatFrameCache own;  // a single frame keeps nothing
    splat_multiresolution(gbuffer, vpls, settings, surface_light, statistics, cache ? *cache : own,
                          image);
  }
  statistics.subsplats = 0;
  for (uint64_t c : statistics.subsplats_per_level) statistics.subsplats += c;

  // §4.3: detail the coarse levels smoothed away, from the angle to the eye (equation 3).
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, image.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (!gbuffer.hit[i]) {
        image[i] = glm::vec3(0.0f);
        continue;
      }
      if (settings.detail_alpha > 0.0f) {
        const float facing = std::max(0.0f, glm::dot(gbuffer.view[i], gbuffer.normal[i]));
        image[i] *= settings.detail_alpha * facing + (1.0f - settings.detail_alpha);
      }
    }
  });
  statistics.seconds_upsample += seconds_since(start);
}

}  // namespace bakegi
