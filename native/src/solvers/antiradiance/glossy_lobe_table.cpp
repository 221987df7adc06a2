#include "solvers/antiradiance/glossy_lobe_table.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <utility>

#include "scene/phong_lobe.h"
#include "solvers/antiradiance/element_hierarchy.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi::antiradiance {

namespace {

constexpr int kAxesPerBin = 32;
constexpr int kDirectionsPerAxis = 64;
// Axes are drawn in a cap of this many bins' solid angle around the bin center and kept when
// they fall in the bin: HEALPix pixels near the poles are elongated, about 2:1.
constexpr double kAxisCapBins = 6.0;
// Lobes wider than this many bin spacings (half width 1/√(n+1)) use bin-center values.
constexpr double kWideLobeSpacings = 2.0;
constexpr int kAlbedoSamples = 257;
// Weights below this fraction of the largest in a lobe are dropped (and the rest renormalized):
// they carry < 1e-4 of the flux in all and would only slow the gather.
constexpr float kRelativeCutoff = 1e-5f;

void build_sampled_lobe(const DirectionalBins& bins, const PhongLobe& lobe, int center,
                        std::vector<double>& histogram) {
  const glm::dvec3 c = glm::dvec3(bins.direction(center));
  const Frame frame{glm::vec3(c)};
  const double cap_cos = 1.0 - 2.0 * kAxisCapBins / bins.bin_count();
  Pcg32 rng(0x9E3779B97F4A7C15ull ^ uint64_t(center), uint64_t(bins.bin_count()));
  int axes = 0;
  for (int tries = 0; axes < kAxesPerBin && tries < 1000 * kAxesPerBin; ++tries) {
    // Uniform in the cap: z uniform in [cap_cos, 1].
    const double z = 1.0 - rng.next_float() * (1.0 - std::max(cap_cos, -1.0));
    const double phi = 2.0 * 3.14159265358979323846 * rng.next_float();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const glm::vec3 axis = glm::normalize(
        frame.to_world(glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z))));
    if (bins.bin_of(axis) != center) continue;
    ++axes;
    // Stratified in (u1, u2): 8 × 8 cells per axis.
    for (int k = 0; k < kDirectionsPerAxis; ++k) {
      const float u1 = (float(k / 8) + rng.next_float()) / 8.0f;
      const float u2 = (float(k % 8) + rng.next_float()) / 8.0f;
      histogram[size_t(bins.bin_of(lobe.sample(axis, std::min(u1, 0.99999994f), u2)))] += 1.0;
    }
  }
  if (axes == 0) histogram[size_t(center)] = 1.0;  // cannot happen for HEALPix; stay defined
}

void build_wide_lobe(const DirectionalBins& bins, const PhongLobe& lobe, int center,
                     std::vector<double>& histogram) {
  const glm::vec3& c = bins.direction(center);
  for (int l = 0; l < bins.bin_count(); ++l) {
    histogram[size_t(l)] = lobe.pdf(glm::dot(c, bins.direction(l)));
  }
}

}  // namespace

GlossyLobeTable::GlossyLobeTable(const DirectionalBins& bins, float exponent)
    : exponent_(exponent), bin_count_(bins.bin_count()) {
  const PhongLobe lobe{exponent};
  const bool wide =
      1.0 / std::sqrt(double(exponent) + 1.0) > kWideLobeSpacings * bins.typical_spacing();
  const int m = bin_count_;
  offsets_.reserve(size_t(m) + 1);
  offsets_.push_back(0);
  std::vector<double> histogram(static_cast<size_t>(m), 0.0);
  std::vector<LobeWeight> entries;
  for (int c = 0; c < m; ++c) {
    std::fill(histogram.begin(), histogram.end(), 0.0);
    if (wide) {
      build_wide_lobe(bins, lobe, c, histogram);
    } else {
      build_sampled_lobe(bins, lobe, c, histogram);
    }
    const double peak = *std::max_element(histogram.begin(), histogram.end());
    entries.clear();
    double total = 0.0;
    for (int l = 0; l < m; ++l) {
      if (histogram[size_t(l)] > kRelativeCutoff * peak) {
        entries.push_back({uint16_t(l), float(histogram[size_t(l)])});
        total += histogram[size_t(l)];
      }
    }
    std::sort(entries.begin(), entries.end(), [](const LobeWeight& a, const LobeWeight& b) {
      return a.weight > b.weight || (a.weight == b.weight && a.bin < b.bin);
    });
    for (LobeWeight& e : entries) e.weight = float(e.weight / total);
    weights_.insert(weights_.end(), entries.begin(), entries.end());
    offsets_.push_back(uint32_t(weights_.size()));
  }
  albedo_.resize(kAlbedoSamples);
  for (int k = 0; k < kAlbedoSamples; ++k) {
    albedo_[size_t(k)] =
        float(phong_directional_albedo(exponent, double(k) / (kAlbedoSamples - 1)));
  }
}

float GlossyLobeTable::directional_albedo(float mu) const {
  const float x = std::clamp(mu, 0.0f, 1.0f) * float(kAlbedoSamples - 1);
  const int k = std::min(int(x), kAlbedoSamples - 2);
  const float t = x - float(k);
  return albedo_[size_t(k)] * (1.0f - t) + albedo_[size_t(k) + 1] * t;
}

size_t GlossyLobeTable::memory_bytes() const {
  return offsets_.size() * sizeof(uint32_t) + weights_.size() * sizeof(LobeWeight) +
         albedo_.size() * sizeof(float);
}

std::shared_ptr<const GlossyLobeTable> GlossyLobeTable::table_for(const DirectionalBins& bins,
                                                                  float exponent) {
  static std::mutex mutex;
  static std::map<std::pair<int, float>, std::shared_ptr<const GlossyLobeTable>> tables;
  const std::pair<int, float> key{bins.bin_count(), exponent};
  {
    std::lock_guard<std::mutex> lock(mutex);
    const auto found = tables.find(key);
    if (found != tables.end()) return found->second;
  }
  // Built outside the lock (other exponents need not wait); a rare duplicate build by two
  // threads gives identical tables, and the first one stored wins.
  auto table = std::make_shared<const GlossyLobeTable>(bins, exponent);
  std::lock_guard<std::mutex> lock(mutex);
  return tables.emplace(key, std::move(table)).first->second;
}

std::vector<const GlossyLobeTable*> glossy_tables_for_patches(
    const std::vector<Patch>& patches, const DirectionalBins& bins,
    std::vector<std::shared_ptr<const GlossyLobeTable>>& keep_alive) {
  std::vector<const GlossyLobeTable*> per_patch(patches.size(), nullptr);
  std::map<float, const GlossyLobeTable*> by_exponent;
  for (size_t p = 0; p < patches.size(); ++p) {
    const Patch& patch = patches[p];
    if (!(max_component(patch.glossy) > 0.0f)) continue;
    auto found = by_exponent.find(patch.glossy_exponent);
    if (found == by_exponent.end()) {
      keep_alive.push_back(GlossyLobeTable::table_for(bins, patch.glossy_exponent));
      found = by_exponent.emplace(patch.glossy_exponent, keep_alive.back().get()).first;
    }
    per_patch[p] = found->second;
  }
  return per_patch;
}

}  // namespace bakegi::antiradiance
