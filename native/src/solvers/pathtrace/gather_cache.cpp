#include "solvers/pathtrace/gather_cache.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "util/job_context.h"
#include "util/random.h"

namespace bakegi {

namespace {

glm::ivec3 cell_of(const glm::vec3& p, float cell) {
  return glm::ivec3(glm::floor(p / cell));
}

uint64_t cell_key(const glm::ivec3& c) {
  // 21 bits a coordinate: +-1M cells, far beyond any cell size the budget allows.
  const auto part = [](int v) { return uint64_t(uint32_t(v + (1 << 20)) & 0x1FFFFFu); };
  return part(c.x) | (part(c.y) << 21) | (part(c.z) << 42);
}

// Which of the six axis directions a normal is closest to.
uint32_t normal_bucket(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const uint32_t axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return axis * 2 + (n[int(axis)] < 0.0f ? 1 : 0);
}

uint64_t slot_hash(uint64_t key) { return mix64(key); }

}  // namespace

float GatherCache::cell_for(double area, uint64_t entries) {
  return float(std::sqrt(0.5 * area / double(std::max<uint64_t>(entries, 1))));
}

std::vector<SurfacePoint> GatherCache::place_entries(const DirectLight& direct,
                                                     const BakePoints& points, float cell,
                                                     uint64_t pilot_rays, uint64_t seed,
                                                     uint64_t& rays, JobContext& context) {
  std::vector<SurfacePoint> hits(pilot_rays);
  std::vector<uint8_t> found(pilot_rays, 0);
  const size_t n = points.size();
  if (n == 0) return {};
  std::atomic<uint64_t> traced{0};
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, pilot_rays, 1024),
                    [&](const tbb::blocked_range<uint64_t>& range) {
                      context.throw_if_cancelled();
                      for (uint64_t k = range.begin(); k != range.end(); ++k) {
                        const size_t i = size_t(k % n);
                        RandomStream rng = sample_stream(seed, i, k / n);
                        const SurfacePoint x{points.positions[i], points.normals[i],
                                             points.normals[i]};
                        const FirstRay ray = sample_first_ray(direct, x, rng);
                        if (!(ray.pdf > 0.0f)) continue;
                        const Hit hit =
                            direct.tracer().intersect(Ray{ray.origin, ray.direction, 0.0f, 1e30f});
                        if (!hit.hit) continue;
                        hits[k] = surface_at_hit(direct.scene(), hit, ray.direction);
                        found[k] = 1;
                      }
                      traced.fetch_add(range.size(), std::memory_order_relaxed);
                    });
  rays += traced.load();
  // One entry per (cell, normal bucket): the first pilot hit there, in pilot order.
  std::vector<std::pair<uint64_t, uint64_t>> keyed;  // (cell key * 8 + bucket, pilot index)
  keyed.reserve(pilot_rays);
  for (uint64_t k = 0; k < pilot_rays; ++k) {
    if (!found[k]) continue;
    const uint64_t key = cell_key(cell_of(hits[k].position, cell));
    keyed.push_back({(key << 3) | normal_bucket(hits[k].shading_normal), k});
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<SurfacePoint> entries;
  for (size_t j = 0; j < keyed.size(); ++j) {
    if (j > 0 && keyed[j].first == keyed[j - 1].first) continue;
    entries.push_back(hits[keyed[j].second]);
  }
  return entries;
}

GatherCache::GatherCache(const std::vector<SurfacePoint>& entries,
                         const std::vector<glm::vec3>& half_a, const std::vector<glm::vec3>& half_b,
                         float cell)
    : cell_(cell) {
  const size_t n = entries.size();
  std::vector<uint64_t> keys(n);
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i) keys[i] = cell_key(cell_of(entries[i].position, cell));
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  positions_.resize(n);
  normals_.resize(n);
  values_.resize(n);
  half_differences_.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const uint32_t i = order[j];
    positions_[j] = entries[i].position;
    normals_[j] = entries[i].shading_normal;
    values_[j] = 0.5f * (half_a[i] + half_b[i]);
    half_differences_[j] = 0.5f * (half_a[i] - half_b[i]);
  }
  size_t capacity = 16;
  while (capacity < 2 * n) capacity *= 2;
  slots_.assign(capacity, Slot{});
  for (size_t j = 0; j < n;) {
    const uint64_t key = keys[order[j]];
    size_t end = j;
    while (end < n && keys[order[end]] == key) ++end;
    size_t s = slot_hash(key) & (capacity - 1);
    while (slots_[s].key != ~uint64_t(0)) s = (s + 1) & (capacity - 1);
    slots_[s] = Slot{key, uint32_t(j), uint32_t(end)};
    j = end;
  }
}

const GatherCache::Slot* GatherCache::find(uint64_t key) const {
  const size_t mask = slots_.size() - 1;
  for (size_t s = slot_hash(key) & mask;; s = (s + 1) & mask) {
    if (slots_[s].key == key) return &slots_[s];
    if (slots_[s].key == ~uint64_t(0)) return nullptr;
  }
}

bool GatherCache::lookup(const glm::vec3& position, const glm::vec3& normal,
                         Reading& out) const {
  if (positions_.empty()) return false;
  // Entries within 1.5 cells, on y's plane to a quarter of that (not a parallel surface
  // nearby: a table top over the floor).
  const float radius = 1.5f * cell_;
  const float radius2 = radius * radius, max_height = 0.25f * radius;
  const glm::ivec3 center = cell_of(position, cell_);
  glm::vec3 sum(0.0f), difference_sum(0.0f);
  float weight_sum = 0.0f;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const Slot* slot = find(cell_key(center + glm::ivec3(dx, dy, dz)));
        if (!slot) continue;
        for (uint32_t j = slot->begin; j < slot->end; ++j) {
          if (glm::dot(normals_[j], normal) < kMinNormalCosine) continue;
          const glm::vec3 offset = positions_[j] - position;
          const float d2 = glm::dot(offset, offset);
          if (d2 >= radius2 || std::abs(glm::dot(offset, normal)) > max_height) continue;
          const float w = 1.0f - d2 / radius2;
          sum += w * values_[j];
          difference_sum += w * half_differences_[j];
          weight_sum += w;
        }
      }
    }
  }
  if (!(weight_sum > 0.0f)) return false;
  out.value = sum / weight_sum;
  out.half_difference = difference_sum / weight_sum;
  return true;
}

}  // namespace bakegi
