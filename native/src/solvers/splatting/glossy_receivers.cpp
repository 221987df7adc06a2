#include "solvers/splatting/glossy_receivers.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "scene/phong_lobe.h"
#include "scene/surface_bsdf.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {
constexpr uint64_t kGlossySalt = 0x676C6F7373794C6Full;  // apart from the diffuse samples
}  // namespace

glm::vec3 vpl_glossy_reflection(const VirtualPointLights& vpls, const glm::vec3& position,
                                const glm::vec3& normal, const glm::vec3& axis, float exponent) {
  // Directions where cos^n α < 1e-4 of the peak add nothing visible: a VPL outside that cone
  // is dropped before the rest of its arithmetic and the power (most VPLs, for a lobe of
  // exponent 16 or more; 30% faster than computing every VPL's geometry over plain floats).
  const float cutoff = exponent > 0.0f ? std::pow(1e-4f, 1.0f / exponent) : 0.0f;
  glm::vec3 sum(0.0f);
  for (size_t v = 0; v < vpls.size(); ++v) {
    const glm::vec3 d = vpls.positions[v] - position;
    const float r2 = glm::dot(d, d);
    const float r = std::sqrt(r2);
    if (!(r > 0.0f)) continue;
    const float cos_alpha = glm::dot(axis, d) / r;
    // A VPL stands for a disk of area π a that subtends about π a / r² from here; a lobe
    // narrower than that would reflect it as a spike (a near mirror: one bright dot per
    // VPL). The lobe widens to the disk's solid angle, 2π / (n + 1) ≥ π a / r², as virtual
    // spherical lights (Hašan et al. 2009) integrate the BRDF over the light's extent.
    const float a = vpls.disk_areas[v];
    // 2 r² / a - 1 < n without the division: most VPLs are far and skip on the cone test.
    const bool widened = 2.0f * r2 < a * (exponent + 1.0f);
    if (!widened && !(cos_alpha > cutoff)) continue;
    const float cos_receiver = glm::dot(normal, d) / r;
    const float cos_vpl = -glm::dot(vpls.normals[v], d) / r;
    if (!(cos_receiver > 0.0f) || !(cos_vpl > 0.0f)) continue;
    const PhongLobe lobe{widened ? std::max(0.0f, 2.0f * r2 / a - 1.0f) : exponent};
    // E = Φ cos cos / (π (r² + A/π)), the VPL's irradiance bounded by its disk.
    sum += vpls.fluxes[v] * (lobe.value(cos_alpha) * cos_receiver * cos_vpl * kInvPi / (r2 + a));
  }
  return sum;
}

bool gathers_lobe(const EyeGBuffer& g, size_t i, float fold_below) {
  return g.hit[i] && max_component(g.glossy[i]) > 0.0f && g.glossy_exponent[i] >= fold_below;
}

void folded_albedo(const EyeGBuffer& g, float fold_below, std::vector<glm::vec3>& out) {
  out.resize(g.size());
  // The quadrature is slow and a scene has few lobes: one value per exponent, found before
  // the pixels are visited in parallel.
  std::map<float, float> albedo_by_exponent;
  for (size_t i = 0; i < g.size(); ++i) {
    if (g.hit[i] && max_component(g.glossy[i]) > 0.0f && !gathers_lobe(g, i, fold_below)) {
      albedo_by_exponent.try_emplace(g.glossy_exponent[i], 0.0f);
    }
  }
  for (auto& [exponent, albedo] : albedo_by_exponent) {
    albedo = float(phong_hemispherical_albedo(exponent));
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, g.size(), 4096), [&](const auto& range) {
    float last_exponent = -1.0f, last_albedo = 0.0f;  // neighbouring pixels share a material
    for (size_t i = range.begin(); i != range.end(); ++i) {
      out[i] = g.albedo[i];
      if (!g.hit[i] || !(max_component(g.glossy[i]) > 0.0f) || gathers_lobe(g, i, fold_below)) {
        continue;
      }
      if (g.glossy_exponent[i] != last_exponent) {
        last_exponent = g.glossy_exponent[i];
        last_albedo = albedo_by_exponent.at(last_exponent);
      }
      out[i] += last_albedo * g.glossy[i];
    }
  });
}

uint64_t glossy_reflection(const EyeGBuffer& g, const DirectLight& direct,
                           const VirtualPointLights& vpls, uint32_t samples, uint64_t seed,
                           float fold_below, std::vector<glm::vec3>& out) {
  out.assign(g.size(), glm::vec3(0.0f));
  uint64_t glossy_pixels = 0;
  for (size_t i = 0; i < g.size(); ++i) glossy_pixels += gathers_lobe(g, i, fold_below);
  if (glossy_pixels == 0) return 0;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, g.size(), 256), [&](const auto& range) {
    uint64_t rays = 0;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      if (!gathers_lobe(g, i, fold_below)) continue;
      const SurfacePoint x{g.position[i], g.normal[i], g.geometric[i]};
      // The lobe alone (the diffuse part is splatted): no diffuse albedo in this BSDF.
      const SurfaceBsdf lobe(x.shading_normal, g.view[i], glm::vec3(0.0f), g.glossy[i],
                             g.glossy_exponent[i]);
      glm::vec3 reflected(0.0f);
      for (uint32_t s = 0; s < samples; ++s) {
        RandomStream rng(sample_pcg(seed ^ kGlossySalt, i, s));
        reflected += direct.sample_lights(x, lobe, rng, rays);
        const float u0 = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
        const BsdfSample ray = lobe.sample(u0, u1, u2);
        if (!(ray.pdf > 0.0f) || glm::dot(ray.direction, x.geometric_normal) <= 0.0f) continue;
        ++rays;
        const Hit hit =
            direct.tracer().intersect(Ray{direct.ray_origin(x), ray.direction, 0.0f, 1e30f});
        reflected += ray.weight * direct.emission_along(x.position, ray.direction, hit, ray.pdf);
      }
      if (samples > 0) reflected /= float(samples);
      const glm::vec3 axis = mirror_direction(x.shading_normal, g.view[i]);
      out[i] = reflected + g.glossy[i] * vpl_glossy_reflection(vpls, x.position, x.shading_normal,
                                                               axis, g.glossy_exponent[i]);
    }
  });
  return glossy_pixels;
}

}  // namespace bakegi
