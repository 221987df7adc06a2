#include "solvers/antiradiance/directional_bins.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace bakegi::antiradiance {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = 0.5 * std::numbers::pi;

// Bins up to 12 · 64² fit 16-bit indices; the ring search needs no more than int.
int clamp_nside(int nside) {
  return std::clamp(nside, 1, DirectionalBins::max_nside);
}

}  // namespace

DirectionalBins::DirectionalBins(int nside)
    : nside_(clamp_nside(nside)),
      bin_count_(12 * nside_ * nside_),
      polar_cap_bins_(2 * nside_ * (nside_ - 1)) {
  directions_.resize(static_cast<size_t>(bin_count_));
  for (int bin = 0; bin < bin_count_; ++bin) {
    double z = 0.0;
    double phi = 0.0;
    bin_center(bin, z, phi);
    const double sin_theta = std::sqrt(std::max(0.0, (1.0 - z) * (1.0 + z)));
    directions_[static_cast<size_t>(bin)] =
        glm::vec3(glm::dvec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), z));
  }

  // Neighbor lists, nearest first (ties by index so the order is deterministic).
  const double radius = neighbor_radius_factor * typical_spacing();
  neighbor_offsets_.reserve(static_cast<size_t>(bin_count_) + 1);
  neighbor_offsets_.push_back(0);
  std::vector<std::pair<double, int>> found;
  for (int bin = 0; bin < bin_count_; ++bin) {
    found.clear();
    for_each_bin_within(glm::dvec3(direction(bin)), radius, [&](int other, double angle) {
      if (other != bin) found.emplace_back(angle, other);
    });
    std::sort(found.begin(), found.end());
    for (const auto& [angle, other] : found) neighbor_bins_.push_back(static_cast<uint16_t>(other));
    neighbor_offsets_.push_back(static_cast<uint32_t>(neighbor_bins_.size()));
  }
}

DirectionalBins DirectionalBins::from_bin_count(int64_t requested_bins) {
  int best = 1;
  for (int nside = 1; nside <= max_nside; ++nside) {
    const int64_t bins = 12 * static_cast<int64_t>(nside) * nside;
    const int64_t best_bins = 12 * static_cast<int64_t>(best) * best;
    if (std::llabs(bins - requested_bins) < std::llabs(best_bins - requested_bins)) best = nside;
  }
  return DirectionalBins(best);
}

double DirectionalBins::solid_angle() const {
  return 4.0 * kPi / bin_count_;
}

double DirectionalBins::typical_spacing() const {
  return std::sqrt(solid_angle());
}

double DirectionalBins::bin_cone_half_angle() const {
  return std::acos(1.0 - 2.0 / static_cast<double>(bin_count_));
}

std::span<const uint16_t> DirectionalBins::neighbors(int bin) const {
  const uint32_t begin = neighbor_offsets_[static_cast<size_t>(bin)];
  const uint32_t end = neighbor_offsets_[static_cast<size_t>(bin) + 1];
  return {neighbor_bins_.data() + begin, end - begin};
}

int DirectionalBins::bin_of(const glm::vec3& direction) const {
  return bin_of(glm::dvec3(direction));
}

// HEALPix ang2pix in the ring scheme (Górski et al. 2005, Eqs. 4–9, as in the reference
// implementation), from a vector so that near the poles 1 − |z| is computed without
// cancellation: 1 − |z| = (x² + y²) / (1 + |z|) on the unit sphere.
int DirectionalBins::bin_of(const glm::dvec3& direction) const {
  const double length = glm::length(direction);
  if (!(length > 0.0) || !std::isfinite(length)) return 0;
  const glm::dvec3 unit = direction / length;
  const double z = std::clamp(unit.z, -1.0, 1.0);
  const double z_abs = std::abs(z);
  const int64_t nside = nside_;
  const int64_t ring_length = 4 * nside;  // bins per equatorial ring

  // tt ∈ [0, 4): longitude in units of π/2.
  double tt = std::atan2(unit.y, unit.x) / kHalfPi;
  if (tt < 0.0) tt += 4.0;
  if (tt >= 4.0) tt = 0.0;

  if (z_abs <= 2.0 / 3.0) {
    // Equatorial belt: the two families of pixel edges are lines in (tt, z); jp and jm count
    // the edges crossed in each family.
    const double a = static_cast<double>(nside) * (0.5 + tt);
    const double b = static_cast<double>(nside) * z * 0.75;
    const int64_t jp = static_cast<int64_t>(a - b);
    const int64_t jm = static_cast<int64_t>(a + b);
    const int64_t ring = nside + 1 + jp - jm;  // 1 .. 2·Nside+1, counted from z = 2/3
    const int64_t shift = 1 - (ring & 1);
    const int64_t t1 = jp + jm - nside + shift + 1 + 2 * ring_length;
    const int64_t index_in_ring = (t1 >> 1) % ring_length;
    return static_cast<int>(polar_cap_bins_ + (ring - 1) * ring_length + index_in_ring);
  }

  // Polar caps: edges are curves of constant √(3(1−|z|))·(tt mod 1) and its complement.
  const double tp = tt - std::floor(tt);
  const double sin_sq = unit.x * unit.x + unit.y * unit.y;
  const double scaled = static_cast<double>(nside) * std::sqrt(3.0 * sin_sq / (1.0 + z_abs));
  const int64_t jp = static_cast<int64_t>(tp * scaled);
  const int64_t jm = static_cast<int64_t>((1.0 - tp) * scaled);
  const int64_t ring = std::min<int64_t>(jp + jm + 1, nside);  // counted from the nearest pole
  int64_t index_in_ring = static_cast<int64_t>(tt * static_cast<double>(ring));
  index_in_ring = std::min(index_in_ring, 4 * ring - 1);
  if (z > 0.0) return static_cast<int>(2 * ring * (ring - 1) + index_in_ring);
  return static_cast<int>(bin_count_ - 2 * ring * (ring + 1) + index_in_ring);
}

// HEALPix pix2ang in the ring scheme.
void DirectionalBins::bin_center(int bin, double& z, double& phi) const {
  const int64_t nside = nside_;
  const int64_t pixel = bin;
  const double inverse_cap = 1.0 / (3.0 * static_cast<double>(nside * nside));
  if (pixel < polar_cap_bins_) {
    // North cap: ring i holds 4i pixels starting at 2i(i−1).
    const int64_t ring =
        (1 + static_cast<int64_t>(std::sqrt(static_cast<double>(1 + 2 * pixel)))) >> 1;
    const int64_t index = pixel + 1 - 2 * ring * (ring - 1);  // 1-based within the ring
    z = 1.0 - static_cast<double>(ring * ring) * inverse_cap;
    phi = (static_cast<double>(index) - 0.5) * kHalfPi / static_cast<double>(ring);
  } else if (pixel < bin_count_ - polar_cap_bins_) {
    // Equatorial belt: rings of 4·Nside pixels, every other ring shifted by half a pixel.
    const int64_t offset = pixel - polar_cap_bins_;
    const int64_t ring = offset / (4 * nside) + nside;
    const int64_t index = offset % (4 * nside) + 1;
    const double shift = ((ring + nside) & 1) ? 1.0 : 0.5;
    z = static_cast<double>(2 * nside - ring) * 2.0 / (3.0 * static_cast<double>(nside));
    phi = (static_cast<double>(index) - shift) * kHalfPi / static_cast<double>(nside);
  } else {
    // South cap, mirrored from the last pixel.
    const int64_t from_end = bin_count_ - pixel;
    const int64_t ring =
        (1 + static_cast<int64_t>(std::sqrt(static_cast<double>(2 * from_end - 1)))) >> 1;
    const int64_t index = 4 * ring + 1 - (from_end - 2 * ring * (ring - 1));
    z = -1.0 + static_cast<double>(ring * ring) * inverse_cap;
    phi = (static_cast<double>(index) - 0.5) * kHalfPi / static_cast<double>(ring);
  }
}

int DirectionalBins::ring_first_bin(int ring) const {
  const int n = nside_;
  if (ring < n) return 2 * ring * (ring - 1);
  if (ring <= 3 * n) return polar_cap_bins_ + (ring - n) * 4 * n;
  const int from_south = 4 * n - ring;
  return bin_count_ - 2 * from_south * (from_south + 1);
}

int DirectionalBins::ring_bin_count(int ring) const {
  const int n = nside_;
  if (ring < n) return 4 * ring;
  if (ring <= 3 * n) return 4 * n;
  return 4 * (4 * n - ring);
}

double DirectionalBins::ring_z(int ring) const {
  const double n = nside_;
  if (ring < nside_) return 1.0 - ring * ring / (3.0 * n * n);
  if (ring <= 3 * nside_) return (2.0 * n - ring) * 2.0 / (3.0 * n);
  const double from_south = 4 * nside_ - ring;
  return -1.0 + from_south * from_south / (3.0 * n * n);
}

void DirectionalBins::for_each_bin_within(
    const glm::dvec3& center, double max_angle,
    const std::function<void(int bin, double angle)>& visit) const {
  const double center_theta = std::acos(std::clamp(center.z, -1.0, 1.0));
  const double cos_max = std::cos(std::min(max_angle, kPi));
  for (int ring = 1; ring <= ring_count(); ++ring) {
    const double ring_theta = std::acos(ring_z(ring));
    // Every center on the ring is at least |θ_ring − θ_center| away.
    if (std::abs(ring_theta - center_theta) > max_angle) continue;
    const int first = ring_first_bin(ring);
    const int count = ring_bin_count(ring);
    for (int bin = first; bin < first + count; ++bin) {
      const double cosine = std::clamp(glm::dot(glm::dvec3(direction(bin)), center), -1.0, 1.0);
      if (cosine >= cos_max) visit(bin, std::acos(cosine));
    }
  }
}

}  // namespace bakegi::antiradiance
