#include "solvers/splatting/vpl_visibility.h"

#include <algorithm>
#include <numeric>

#include "scene/ray_tracer.h"
#include "util/luminance.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

uint64_t spread_bits(uint64_t v) {  // 21 bits to every third of 63
  v &= 0x1FFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

VplClusters cluster_vpls(VirtualPointLights& vpls, uint32_t count) {
  VplClusters clusters;
  const size_t n = vpls.size();
  if (n == 0 || count == 0) return clusters;
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : vpls.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::vec3 scale = glm::vec3(2097151.0f) / glm::max(hi - lo, glm::vec3(1e-12f));
  std::vector<uint64_t> keys(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3 q = (vpls.positions[i] - lo) * scale;
    keys[i] = spread_bits(uint64_t(q.x)) | spread_bits(uint64_t(q.y)) << 1 |
              spread_bits(uint64_t(q.z)) << 2;
  }
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return keys[a] < keys[b]; });
  VirtualPointLights sorted;
  const bool has_texels = vpls.texel_begin.size() == n + 1;
  if (has_texels) sorted.texel_begin.push_back(0);
  for (size_t i : order) {
    sorted.positions.push_back(vpls.positions[i]);
    sorted.normals.push_back(vpls.normals[i]);
    sorted.fluxes.push_back(vpls.fluxes[i]);
    sorted.disk_areas.push_back(vpls.disk_areas[i]);
    if (!has_texels) continue;
    sorted.texels.insert(sorted.texels.end(), vpls.texels.begin() + vpls.texel_begin[i],
                         vpls.texels.begin() + vpls.texel_begin[i + 1]);
    sorted.texel_begin.push_back(uint32_t(sorted.texels.size()));
  }
  vpls = std::move(sorted);
  const size_t c = std::min<size_t>(count, n);
  const float offset = 1e-4f * glm::length(hi - lo) + 1e-6f;
  for (size_t k = 0; k <= c; ++k) clusters.begin.push_back(k * n / c);
  for (size_t k = 0; k < c; ++k) {
    glm::dvec3 centre(0.0);
    double weight = 0.0;
    for (size_t v = clusters.begin[k]; v < clusters.begin[k + 1]; ++v) {
      const double w = std::max(luminance(vpls.fluxes[v]), 1e-30);
      centre += glm::dvec3(vpls.positions[v]) * w;
      weight += w;
    }
    centre /= weight;
    size_t best = clusters.begin[k];
    double best_d = 1e300;
    for (size_t v = clusters.begin[k]; v < clusters.begin[k + 1]; ++v) {
      const glm::dvec3 d = glm::dvec3(vpls.positions[v]) - centre;
      if (glm::dot(d, d) < best_d) best_d = glm::dot(d, d), best = v;
    }
    // Ends just off the VPL's surface, on its lit side: a ray from behind that surface must
    // meet it before the end.
    clusters.anchor.push_back(vpls.positions[best] + vpls.normals[best] * offset);
  }
  return clusters;
}

glm::vec3 visible_vpl_light(const VplClusters& clusters, const RayTracer& tracer, float epsilon,
                            const glm::vec3& position, const glm::vec3& geometric_normal,
                            const VplRangeLight& range_light, uint64_t& rays) {
  glm::vec3 sum(0.0f);
  const glm::vec3 origin = position + geometric_normal * epsilon;
  for (size_t c = 0; c < clusters.count(); ++c) {
    const glm::vec3 light = range_light(clusters.begin[c], clusters.begin[c + 1]);
    if (!(max_component(light) > 0.0f)) continue;
    const glm::vec3 to = clusters.anchor[c] - origin;
    const float distance = glm::length(to);
    if (!(distance > 2.0f * epsilon)) {
      sum += light;
      continue;
    }
    Ray ray;
    ray.origin = origin;
    ray.direction = to / distance;
    ray.tnear = 0.0f;
    ray.tfar = distance - 2.0f * epsilon;
    ++rays;
    if (!tracer.occluded(ray)) sum += light;
  }
  return sum;
}

}  // namespace bakegi
