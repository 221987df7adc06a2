#include "solvers/antiradiance/bin_spreading.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace bakegi::antiradiance {

namespace {

constexpr double kPi = std::numbers::pi;

// Support of a filter in units of the Gaussian's σ beyond the cone's edge.
constexpr double kSupportSigmas = 2.5;
// The Gaussian itself is integrated out to 5σ, where it is below 4e-6 of its peak.
constexpr double kGaussianSigmas = 5.0;
constexpr int kProfileSamples = 1024;
constexpr int kGaussianSteps = 512;

// The cap of half-angle `cone` around the pole, prefiltered by the Gaussian of standard
// deviation `sigma`, sampled at angles θ_i = i · step from the pole, i = 0 .. samples − 1.
// In a frame around the evaluation direction P (at angle θ from the pole A), the points at
// angle γ from P form a circle; the part of it inside the cap is where
// cos θ cos γ + sin θ sin γ cos φ ≥ cos α, an arc of 2·acos(c) with
// c = (cos α − cos θ cos γ) / (sin θ sin γ). So the 2D integral becomes a 1D integral over γ
// with that arc length, which is non-increasing in θ for every γ: the profile falls with angle.
std::vector<double> filtered_cap_profile(double cone, double sigma, double step, int samples) {
  const double gamma_max = std::min(kPi, kGaussianSigmas * sigma);
  const double d_gamma = gamma_max / kGaussianSteps;
  std::vector<double> ring_weight(kGaussianSteps);
  std::vector<double> cos_gamma(kGaussianSteps);
  std::vector<double> sin_gamma(kGaussianSteps);
  for (int s = 0; s < kGaussianSteps; ++s) {
    const double gamma = (s + 0.5) * d_gamma;  // midpoint rule
    cos_gamma[s] = std::cos(gamma);
    sin_gamma[s] = std::sin(gamma);
    ring_weight[s] = std::exp(-0.5 * gamma * gamma / (sigma * sigma)) * sin_gamma[s] * d_gamma;
  }
  const double cos_cone = std::cos(cone);
  std::vector<double> profile(static_cast<size_t>(samples));
  for (int i = 0; i < samples; ++i) {
    const double theta = std::min(kPi, i * step);
    const double cos_theta = std::cos(theta);
    const double sin_theta = std::sin(theta);
    double sum = 0.0;
    for (int s = 0; s < kGaussianSteps; ++s) {
      const double denominator = sin_theta * sin_gamma[s];
      double arc = 0.0;
      if (denominator < 1e-12) {
        arc = cos_theta * cos_gamma[s] >= cos_cone ? 2.0 * kPi : 0.0;
      } else {
        const double c = (cos_cone - cos_theta * cos_gamma[s]) / denominator;
        arc = 2.0 * std::acos(std::clamp(c, -1.0, 1.0));
      }
      sum += ring_weight[s] * arc;
    }
    profile[static_cast<size_t>(i)] = sum;
  }
  return profile;
}

}  // namespace

BinSpreading::BinSpreading(const DirectionalBins& bins, double max_half_angle)
    : bin_count_(bins.bin_count()), bin_half_angle_(bins.bin_cone_half_angle()) {
  identity_bins_.resize(static_cast<size_t>(bin_count_));
  std::iota(identity_bins_.begin(), identity_bins_.end(), uint16_t{0});

  half_angles_.push_back(bin_half_angle_);
  const double max_angle = std::min(max_half_angle, kPi);
  for (int k = 1; half_angles_.back() < max_angle; ++k) {
    half_angles_.push_back(std::min(max_angle, bin_half_angle_ * std::exp2(0.5 * k)));
  }

  const double sigma = bins.typical_spacing();
  std::vector<std::pair<double, int>> support;
  for (size_t k = 1; k < half_angles_.size(); ++k) {
    const double cone = half_angles_[k];
    const double radius = std::min(kPi, cone + kSupportSigmas * sigma);
    const double step = radius / (kProfileSamples - 2);
    const std::vector<double> profile = filtered_cap_profile(cone, sigma, step, kProfileSamples);

    ClassTable table;
    table.offsets.reserve(static_cast<size_t>(bin_count_) + 1);
    table.offsets.push_back(0);
    for (int center = 0; center < bin_count_; ++center) {
      support.clear();
      bins.for_each_bin_within(glm::dvec3(bins.direction(center)), radius,
                               [&](int bin, double angle) { support.emplace_back(angle, bin); });
      std::sort(support.begin(), support.end());
      const size_t first = table.weights.size();
      double total = 0.0;
      for (const auto& [angle, bin] : support) {
        const double position = angle / step;
        const int below = std::min(static_cast<int>(position), kProfileSamples - 2);
        const double t = position - below;
        const double weight = (1.0 - t) * profile[static_cast<size_t>(below)] +
                              t * profile[static_cast<size_t>(below) + 1];
        table.bins.push_back(static_cast<uint16_t>(bin));
        table.weights.push_back(static_cast<float>(weight));
        total += weight;
      }
      // The center bin always has positive weight, so total > 0.
      const double scale = 1.0 / total;
      for (size_t e = first; e < table.weights.size(); ++e) {
        table.weights[e] = static_cast<float>(table.weights[e] * scale);
      }
      table.offsets.push_back(static_cast<uint32_t>(table.weights.size()));
    }
    table.bins.shrink_to_fit();
    table.weights.shrink_to_fit();
    tables_.push_back(std::move(table));
  }
}

int BinSpreading::class_of(double cone_solid_angle) const {
  const double bin_solid_angle = 4.0 * kPi / bin_count_;
  if (!(cone_solid_angle > bin_solid_angle) || class_count() == 1) return 0;
  const double cone = std::acos(std::clamp(1.0 - cone_solid_angle / (2.0 * kPi), -1.0, 1.0));
  // Nearest in log half-angle among the classes (the last one may be clamped, so compare
  // with the actual half-angles rather than rounding the exponent); at most a dozen classes.
  int best = 1;
  for (int k = 2; k < class_count(); ++k) {
    if (std::abs(std::log(cone / half_angles_[static_cast<size_t>(k)])) <
        std::abs(std::log(cone / half_angles_[static_cast<size_t>(best)]))) {
      best = k;
    }
  }
  return best;
}

SpreadFilter BinSpreading::filter(int cone_class, int bin) const {
  if (cone_class == 0) {
    return {{identity_bins_.data() + bin, 1}, {&identity_weight_, 1}};
  }
  const ClassTable& table = tables_[static_cast<size_t>(cone_class) - 1];
  const uint32_t begin = table.offsets[static_cast<size_t>(bin)];
  const uint32_t end = table.offsets[static_cast<size_t>(bin) + 1];
  return {{table.bins.data() + begin, end - begin}, {table.weights.data() + begin, end - begin}};
}

size_t BinSpreading::memory_bytes() const {
  size_t bytes = identity_bins_.size() * sizeof(uint16_t) + sizeof(identity_weight_);
  for (const ClassTable& table : tables_) {
    bytes += table.offsets.size() * sizeof(uint32_t) + table.bins.size() * sizeof(uint16_t) +
             table.weights.size() * sizeof(float);
  }
  return bytes;
}

}  // namespace bakegi::antiradiance
