#include "solvers/pathtrace/direction_guide.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "lights/direct_light.h"
#include "solvers/pathtrace/indirect_path.h"
#include "util/job_context.h"
#include "util/luminance.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

constexpr float kBinSolidAngle = 4.0f * kPi / float(DirectionGuide::kBins);

int bin_of(const glm::vec3& d) {
  const int zi = std::clamp(int((d.z + 1.0f) * 0.5f * float(DirectionGuide::kZBins)), 0,
                            DirectionGuide::kZBins - 1);
  float phi = std::atan2(d.y, d.x);
  if (phi < 0.0f) phi += 2.0f * kPi;
  const int pi = std::clamp(int(phi / (2.0f * kPi) * float(DirectionGuide::kPhiBins)), 0,
                            DirectionGuide::kPhiBins - 1);
  return zi * DirectionGuide::kPhiBins + pi;
}

// Which of the six axis directions a normal is closest to.
uint32_t normal_bucket(const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const uint32_t axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  return axis * 2 + (n[int(axis)] < 0.0f ? 1 : 0);
}

}  // namespace

uint64_t DirectionGuide::key_of(const glm::vec3& position, const glm::vec3& normal) const {
  const glm::vec3 c = glm::floor((position - origin_) / cell_);
  const auto part = [](float v) {
    return uint64_t(std::clamp<int64_t>(int64_t(v), 0, (int64_t(1) << 20) - 1));
  };
  return part(c.x) | (part(c.y) << 20) | (part(c.z) << 40) |
         (uint64_t(normal_bucket(normal)) << 60);
}

DirectionGuide::DirectionGuide(const DirectLight& direct, const BakePoints& points, int paths,
                               int max_bounces, uint64_t seed, JobContext& context) {
  const size_t n = points.size();
  if (n == 0) return;
  glm::vec3 lo(points.positions[0]), hi(points.positions[0]);
  for (const glm::vec3& p : points.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  origin_ = lo;
  // Cells sized so that occupied ones hold about kPointsPerRegion points: the points lie on
  // surfaces, so the count per cell goes as the cell's side squared.
  cell_ = std::max(glm::length(hi - lo), 1e-6f) / 16.0f;
  for (int pass = 0; pass < 3; ++pass) {
    std::unordered_map<uint64_t, int> count;
    for (size_t i = 0; i < n; ++i) ++count[key_of(points.positions[i], points.normals[i])];
    const double mean = double(n) / double(count.size());
    cell_ *= float(std::clamp(std::sqrt(kPointsPerRegion / mean), 0.25, 4.0));
    cell_ = std::max(cell_, std::max(glm::length(hi - lo), 1e-6f) * 1e-5f);
  }
  std::vector<int> region(n);
  for (size_t i = 0; i < n; ++i) {
    const auto [it, added] = region_of_key_.try_emplace(
        key_of(points.positions[i], points.normals[i]), int(region_of_key_.size()));
    region[i] = it->second;
  }
  const size_t regions = region_of_key_.size();

  // Training: each bin sums the values of the paths that left through it, a histogram of
  // L cos / pi (the paths are drawn with density cos / pi). Values above kClampOverMean times
  // their region's mean are cut to it: one rare bright path would otherwise send half of
  // every later path into its bin.
  struct Sample {
    uint32_t region;
    uint32_t bin;
    float value;
  };
  tbb::enumerable_thread_specific<std::vector<Sample>> local_samples;
  std::atomic<uint64_t> rays{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 64),
                    [&](const tbb::blocked_range<size_t>& range) {
                      context.throw_if_cancelled();
                      std::vector<Sample>& samples = local_samples.local();
                      uint64_t block_rays = 0;
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const SurfacePoint x{points.positions[i], points.normals[i],
                                             points.normals[i]};
                        for (int k = 0; k < paths; ++k) {
                          RandomStream rng = sample_stream(seed, i, uint64_t(k));
                          const FirstRay first = sample_first_ray(direct, x, rng);
                          if (!(first.pdf > 0.0f)) continue;
                          ++block_rays;
                          const Hit hit = direct.tracer().intersect(
                              Ray{first.origin, first.direction, 0.0f, 1e30f});
                          const PathRadiance path = trace_from_first_hit(
                              direct, hit, first.direction, rng, max_bounces, block_rays);
                          const double y = luminance(path.first_light + path.rest);
                          if (y > 0.0 && std::isfinite(y)) {
                            samples.push_back(
                                {uint32_t(region[i]), uint32_t(bin_of(first.direction)), float(y)});
                          }
                        }
                      }
                      rays.fetch_add(block_rays, std::memory_order_relaxed);
                    });
  context.throw_if_cancelled();
  rays_ = rays.load();
  std::vector<double> region_sum(regions, 0.0), region_count(regions, 0.0);
  for (const std::vector<Sample>& samples : local_samples) {
    for (const Sample& s : samples) {
      region_sum[s.region] += s.value;
      region_count[s.region] += 1.0;
    }
  }
  const double clamp_over_mean = getenv("BAKEGI_GUIDE_CLAMP") ? atof(getenv("BAKEGI_GUIDE_CLAMP")) : 1e30;
  std::vector<double> mass(regions * kBins, 0.0);
  for (const std::vector<Sample>& samples : local_samples) {
    for (const Sample& s : samples) {
      const double limit = clamp_over_mean * region_sum[s.region] / region_count[s.region];
      mass[size_t(s.region) * kBins + s.bin] += std::min(double(s.value), limit);
    }
  }
  cdf_.assign(regions * kBins, 0.0f);
  probability_.assign(regions * kBins, 0.0f);
  for (size_t r = 0; r < regions; ++r) {
    double total = 0.0;
    for (int b = 0; b < kBins; ++b) total += mass[r * kBins + size_t(b)];
    if (!(total > 0.0)) continue;  // saw no light: left out (region_of says -1)
    double running = 0.0;
    for (int b = 0; b < kBins; ++b) {
      const double p = mass[r * kBins + size_t(b)] / total;
      probability_[r * kBins + size_t(b)] = float(p);
      running += p;
      cdf_[r * kBins + size_t(b)] = float(running);
    }
    cdf_[r * kBins + kBins - 1] = 1.0f;
  }
}

int DirectionGuide::region_of(const glm::vec3& position, const glm::vec3& normal) const {
  const auto it = region_of_key_.find(key_of(position, normal));
  if (it == region_of_key_.end()) return -1;
  // A region whose training saw no light has no histogram.
  return cdf_[size_t(it->second) * kBins + kBins - 1] > 0.0f ? it->second : -1;
}

glm::vec3 DirectionGuide::sample(int region, float u1, float u2) const {
  const float* cdf = &cdf_[size_t(region) * kBins];
  // Pick the bin by u1, and reuse u1's position inside the bin for z (keeps it uniform).
  const int bin = int(std::min<ptrdiff_t>(std::upper_bound(cdf, cdf + kBins, u1) - cdf, kBins - 1));
  const float below = bin > 0 ? cdf[bin - 1] : 0.0f;
  const float width = cdf[bin] - below;
  const float t = width > 0.0f ? std::clamp((u1 - below) / width, 0.0f, 0.99999994f) : 0.5f;
  const int zi = bin / kPhiBins, pi = bin % kPhiBins;
  const float z = -1.0f + 2.0f * (float(zi) + t) / float(kZBins);
  const float phi = 2.0f * kPi * (float(pi) + u2) / float(kPhiBins);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
}

float DirectionGuide::pdf(int region, const glm::vec3& direction) const {
  return probability_[size_t(region) * kBins + size_t(bin_of(direction))] / kBinSolidAngle;
}

}  // namespace bakegi
