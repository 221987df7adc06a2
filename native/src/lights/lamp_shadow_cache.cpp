#include "lights/lamp_shadow_cache.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "scene/scene.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

LampShadowCache LampShadowCache::build(const Scene& scene, const DirectLight& direct,
                                       uint64_t& rays, size_t points, int cells_per_side) {
  LampShadowCache cache;
  const size_t lamps = std::min(direct.lamp_count(), kMaxJudgedLamps);
  if (lamps == 0 || scene.triangles.empty()) return cache;
  if (points == 0) {
    points = lamps <= 4 ? size_t(1) << 16 : std::max(size_t(1) << 14, (size_t(1) << 18) / lamps);
  }
  const glm::vec3 size = glm::max(scene.bounds_max - scene.bounds_min, glm::vec3(1e-6f));
  const float cell = std::max({size.x, size.y, size.z}) / float(std::max(cells_per_side, 1));
  cache.origin_ = scene.bounds_min;
  cache.inverse_cell_ = 1.0f / cell;
  cache.resolution_ = glm::max(glm::ivec3(glm::ceil(size / cell)), glm::ivec3(1));
  const size_t cells = size_t(cache.resolution_.x) * cache.resolution_.y * cache.resolution_.z * 6;

  // Points by area: the cumulative areas, searched with one number per point.
  std::vector<double> cumulative(scene.triangles.size());
  double total = 0.0;
  for (size_t i = 0; i < scene.triangles.size(); ++i) {
    total += scene.triangles[i].area;
    cumulative[i] = total;
  }
  if (!(total > 0.0)) return cache;

  // Per lamp and cell: pilot rays, and those that reached the lamp (atomic sums: the same
  // totals in any order, so the cache does not depend on the threads' schedule).
  std::vector<std::unique_ptr<std::atomic<uint32_t>[]>> tested(lamps), seen(lamps);
  for (size_t k = 0; k < lamps; ++k) {
    if (!direct.lamp_casts_shadow(k)) continue;
    tested[k].reset(new std::atomic<uint32_t>[cells]());
    seen[k].reset(new std::atomic<uint32_t>[cells]());
  }
  std::atomic<uint64_t> traced{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points, 1024), [&](const auto& range) {
    uint64_t local_rays = 0;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      RandomStream rng(mix64(0x5EEDC0DEull ^ i), 0x4C616D70ull);
      const double pick = rng.next_float() * total;
      const size_t t = std::min<size_t>(
          size_t(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()),
          scene.triangles.size() - 1);
      const Triangle& triangle = scene.triangles[t];
      const glm::vec2 b = sample_triangle_barycentrics(rng.next_float(), rng.next_float());
      const glm::vec3 p =
          triangle.p[0] * (1.0f - b.x - b.y) + triangle.p[1] * b.x + triangle.p[2] * b.y;
      for (size_t k = 0; k < lamps; ++k) {
        if (!tested[k]) continue;
        LightSample s;
        const float u1 = rng.next_float(), u2 = rng.next_float();
        if (!direct.sample_lamp(k, p, u1, u2, s)) continue;
        const float facing = glm::dot(triangle.face_normal, s.direction);
        if (facing == 0.0f) continue;
        const glm::vec3 side = facing > 0.0f ? triangle.face_normal : -triangle.face_normal;
        const SurfacePoint x{p, side, side};
        const int64_t c = cache.cell_of(p, side);
        if (c < 0) continue;
        tested[k][size_t(c)].fetch_add(1, std::memory_order_relaxed);
        if (direct.unoccluded(x, s, local_rays)) {
          seen[k][size_t(c)].fetch_add(1, std::memory_order_relaxed);
        }
      }
    }
    traced.fetch_add(local_rays, std::memory_order_relaxed);
  });
  rays += traced.load();

  cache.blocked_.assign(lamps, {});
  cache.judged_.assign(lamps, 0);
  for (size_t k = 0; k < lamps; ++k) {
    if (!tested[k]) continue;
    std::vector<uint8_t>& blocked = cache.blocked_[k];
    blocked.assign(cells, 0);
    for (size_t c = 0; c < cells; ++c) {
      const uint32_t n = tested[k][c].load(std::memory_order_relaxed);
      if (n < kMinimumTests) continue;
      ++cache.judged_[k];
      blocked[c] = seen[k][c].load(std::memory_order_relaxed) == 0 ? 1 : 0;
    }
  }
  return cache;
}

std::vector<float> LampShadowCache::blocked_shares() const {
  std::vector<float> shares(blocked_.size(), 0.0f);
  for (size_t k = 0; k < blocked_.size(); ++k) {
    if (judged_[k] == 0) continue;
    size_t blocked = 0;
    for (uint8_t b : blocked_[k]) blocked += b;
    shares[k] = float(blocked) / float(judged_[k]);
  }
  return shares;
}

}  // namespace bakegi
