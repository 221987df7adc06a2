#include "solvers/pathtrace/irradiance_gradients.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/luminance.h"
#include "util/sampling.h"

namespace bakegi {

namespace {

constexpr int M = HemisphereCells::kThetaCells;
constexpr int N = HemisphereCells::kPhiCells;

int cell_of(float u1, float u2) {
  const int j = std::clamp(int(u1 * float(M)), 0, M - 1);
  const int k = std::clamp(int(u2 * float(N)), 0, N - 1);
  return j * N + k;
}

// sin θ and cos θ where u1 = sin² θ (the cosine-distributed polar angle).
double sin_theta(double u1) {
  return std::sqrt(std::clamp(u1, 0.0, 1.0));
}
double cos_theta(double u1) {
  return std::sqrt(std::clamp(1.0 - u1, 0.0, 1.0));
}

glm::dvec3 azimuth(double phi) {
  return {std::cos(phi), std::sin(phi), 0.0};
}
glm::dvec3 perpendicular(double phi) {
  return {-std::sin(phi), std::cos(phi), 0.0};
}

// 1 / min(a, b) with misses (+inf) contributing nothing.
double inverse_nearest(float a, float b) {
  const float r = std::min(a, b);
  return std::isfinite(r) && r > 0.0f ? 1.0 / double(r) : 0.0;
}

}  // namespace

glm::vec3 HemisphereCells::local_direction(float u1, float u2) {
  const float s = float(sin_theta(u1)), c = float(cos_theta(u1));
  const float phi = 2.0f * float(M_PI) * u2;
  return {s * std::cos(phi), s * std::sin(phi), c};
}

void HemisphereCells::add(float u1, float u2, const glm::vec3& radiance, float distance) {
  Cell& cell = cells_[size_t(cell_of(u1, u2))];
  cell.nearest = cell.samples == 0 ? distance : std::min(cell.nearest, distance);
  cell.radiance += glm::dvec3(radiance);
  cell.squares += glm::dvec3(radiance) * glm::dvec3(radiance);
  ++cell.samples;
  ++samples_;
  total_squares_ += glm::dvec3(radiance) * glm::dvec3(radiance);
  if (std::isfinite(distance) && distance > 0.0f) inverse_distance_sum_ += 1.0 / distance;
  const double y = luminance(radiance);
  luminance_sum_ += y;
  luminance_squares_ += y * y;
}

IrradianceGather HemisphereCells::estimate(const Frame& frame) const {
  IrradianceGather out;
  out.samples = samples_;
  if (samples_ == 0) return out;
  const double n = double(samples_);
  glm::dvec3 total(0.0);
  for (const Cell& cell : cells_) total += cell.radiance;
  const glm::dvec3 mean = total / n;
  out.value = glm::vec3(mean);
  out.harmonic_distance = inverse_distance_sum_ > 0.0 ? float(n / inverse_distance_sum_)
                                                      : std::numeric_limits<float>::infinity();
  out.luminance_sum = luminance_sum_;
  out.luminance_squares = luminance_squares_;
  if (samples_ > 1) {
    const double y = luminance_sum_ / n;
    out.luminance_variance_of_mean =
        float(std::max(0.0, (luminance_squares_ - n * y * y) / (n - 1.0)) / n);
  }

  // Cell means (an empty cell reads as the mean), the variance of each mean (a cell of one
  // sample borrows the gather's per-sample variance), and nearest hits.
  const glm::dvec3 sample_variance =
      glm::max(glm::dvec3(0.0), (total_squares_ - n * mean * mean) / std::max(1.0, n - 1.0));
  std::array<glm::dvec3, kCells> radiance, mean_variance;
  std::array<float, kCells> nearest;
  for (int c = 0; c < kCells; ++c) {
    const Cell& cell = cells_[size_t(c)];
    const double m = double(cell.samples);
    radiance[size_t(c)] = cell.samples > 0 ? cell.radiance / m : mean;
    mean_variance[size_t(c)] =
        cell.samples > 1
            ? glm::max(glm::dvec3(0.0),
                       (cell.squares - cell.radiance * cell.radiance / m) / (m - 1.0)) /
                  m
        : cell.samples == 1 ? sample_variance
                            : glm::dvec3(0.0);
    nearest[size_t(c)] = cell.samples > 0 ? cell.nearest : std::numeric_limits<float>::infinity();
  }
  const auto at = [](int j, int k) { return size_t(j * N + (k + N) % N); };

  // Both gradients are linear in the cell means: gradient = Σ_c coefficient_c L_c (local
  // frame), so their noise is Σ_c |coefficient_c|² Var(L_c).
  std::array<glm::dvec3, kCells> rotation{}, translation{};
  const double dphi = 2.0 * M_PI / double(N);
  for (int k = 0; k < N; ++k) {
    const glm::dvec3 u_k = azimuth((k + 0.5) * dphi), v_k = perpendicular((k + 0.5) * dphi);
    const glm::dvec3 v_boundary = perpendicular(k * dphi);
    for (int j = 0; j < M; ++j) {
      const double u_centre = (j + 0.5) / M, u_low = double(j) / M, u_high = (j + 1.0) / M;
      // Rotation: L tan θ v over the cells.
      rotation[at(j, k)] += (sin_theta(u_centre) / cos_theta(u_centre) / double(kCells)) * v_k;
      // Translation across the cell's lower polar boundary (j >= 1) and its lower azimuthal
      // boundary (between k - 1 and k), each a difference of two cells.
      if (j >= 1) {
        const double s = sin_theta(u_low), c = cos_theta(u_low);
        const glm::dvec3 polar = (dphi * s * c * c / M_PI) *
                                 inverse_nearest(nearest[at(j, k)], nearest[at(j - 1, k)]) * u_k;
        translation[at(j, k)] += polar;
        translation[at(j - 1, k)] -= polar;
      }
      const glm::dvec3 azimuthal = ((sin_theta(u_high) - sin_theta(u_low)) / M_PI) *
                                   inverse_nearest(nearest[at(j, k)], nearest[at(j, k - 1)]) *
                                   v_boundary;
      translation[at(j, k)] += azimuthal;
      translation[at(j, k - 1)] -= azimuthal;
    }
  }
  const auto gradient_of = [&](const std::array<glm::dvec3, kCells>& coefficient,
                               std::array<glm::vec3, 3>& gradient, glm::vec3& noise_out) {
    for (int channel = 0; channel < 3; ++channel) {
      glm::dvec3 g(0.0);
      double noise = 0.0;
      for (int c = 0; c < kCells; ++c) {
        g += coefficient[size_t(c)] * radiance[size_t(c)][channel];
        noise += glm::dot(coefficient[size_t(c)], coefficient[size_t(c)]) *
                 mean_variance[size_t(c)][channel];
      }
      gradient[size_t(channel)] = frame.to_world(glm::vec3(g));
      noise_out[channel] = float(noise);
    }
  };
  gradient_of(rotation, out.rotational, out.rotational_noise);
  gradient_of(translation, out.translational, out.translational_noise);
  return out;
}

namespace {

// E|ĝ|² = |g|² + noise: keeps the part of the estimate above its noise, per channel.
void shrink(std::array<glm::vec3, 3>& gradient, glm::vec3& noise) {
  for (int channel = 0; channel < 3; ++channel) {
    glm::vec3& g = gradient[size_t(channel)];
    const double squared = glm::dot(glm::dvec3(g), glm::dvec3(g));
    const double keep =
        squared > 0.0 ? std::max(0.0, squared - double(noise[channel])) / squared : 0.0;
    g *= float(keep);
    noise[channel] = 0.0f;
  }
}

}  // namespace

IrradianceGather shrink_gradients(const IrradianceGather& gather) {
  IrradianceGather out = gather;
  shrink(out.rotational, out.rotational_noise);
  shrink(out.translational, out.translational_noise);
  return out;
}

IrradianceGather combine_gathers(const IrradianceGather& a, const IrradianceGather& b) {
  if (a.samples == 0) return b;
  if (b.samples == 0) return a;
  const double n = double(a.samples + b.samples);
  const float wa = float(double(a.samples) / n), wb = float(double(b.samples) / n);
  IrradianceGather out;
  out.samples = a.samples + b.samples;
  out.value = wa * a.value + wb * b.value;
  for (size_t c = 0; c < 3; ++c) {
    out.rotational[c] = wa * a.rotational[c] + wb * b.rotational[c];
    out.translational[c] = wa * a.translational[c] + wb * b.translational[c];
  }
  out.rotational_noise = wa * wa * a.rotational_noise + wb * wb * b.rotational_noise;
  out.translational_noise = wa * wa * a.translational_noise + wb * wb * b.translational_noise;
  // Σ 1/r of each gather is samples / harmonic mean (0 for +inf).
  const auto inverse_sum = [](const IrradianceGather& g) {
    return std::isfinite(g.harmonic_distance) && g.harmonic_distance > 0.0f
               ? double(g.samples) / double(g.harmonic_distance)
               : 0.0;
  };
  const double inverse = inverse_sum(a) + inverse_sum(b);
  out.harmonic_distance =
      inverse > 0.0 ? float(n / inverse) : std::numeric_limits<float>::infinity();
  out.luminance_sum = a.luminance_sum + b.luminance_sum;
  out.luminance_squares = a.luminance_squares + b.luminance_squares;
  const double y = out.luminance_sum / n;
  out.luminance_variance_of_mean =
      float(std::max(0.0, (out.luminance_squares - n * y * y) / (n - 1.0)) / n);
  return out;
}

}  // namespace bakegi
