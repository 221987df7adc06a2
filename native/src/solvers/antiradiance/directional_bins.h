// The directional discretization of §3.1: the sphere of directions split into m bins of equal
// solid angle 4π/m, with main directions ω_j. We use the HEALPix ring scheme (Górski et al.
// 2005, "HEALPix: a framework for high-resolution discretization and fast analysis of data
// distributed on the sphere"): m = 12·Nside² equal-area pixels on 4·Nside − 1 iso-latitude
// rings, numbered from the north pole (+z) ring by ring, east from φ = 0 (φ = atan2(y, x)).
// Nside 2..16 gives 48..3072 bins. The lookup of the bin of a direction is the closed-form
// ang2pix (O(1)); the centers come from pix2ang. Both are implemented here from the published
// formulas, so the solver needs no extra dependency.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi::antiradiance {

class DirectionalBins {
 public:
  // Nside is clamped to [1, max_nside]; max_nside keeps bin indices within 16 bits, which the
  // spreading tables rely on (12 · 64² = 49152 bins).
  static constexpr int max_nside = 64;

  explicit DirectionalBins(int nside);

  // The Nside whose 12·Nside² is closest to `requested_bins` (ties to the smaller Nside, so
  // memory never grows past what the tie allows), clamped to [1, max_nside]. For example 128
  // gives Nside 3 (108 bins), 192 gives Nside 4 (192), 512 gives Nside 7 (588), 1024 gives
  // Nside 9 (972), 3072 gives Nside 16.
  static DirectionalBins from_bin_count(int64_t requested_bins);

  int nside() const { return nside_; }
  int bin_count() const { return bin_count_; }
  int ring_count() const { return 4 * nside_ - 1; }

  // ω_bin = 4π/m, the same for every bin (equal area).
  double solid_angle() const;
  // sqrt(4π/m): the angle between a bin and its closest neighbor for an ideal uniform
  // distribution; the standard deviation of the spreading Gaussian (§3.1).
  double typical_spacing() const;
  // Half-angle of the cone whose solid angle is one bin: cos α = 1 − 2/m.
  double bin_cone_half_angle() const;

  // Unit main direction ω_j of bin j (the HEALPix pixel center).
  const glm::vec3& direction(int bin) const { return directions_[static_cast<size_t>(bin)]; }
  // The bin containing `direction` (need not be normalized). The zero vector and non-finite
  // input map to bin 0 rather than failing.
  int bin_of(const glm::vec3& direction) const;
  int bin_of(const glm::dvec3& direction) const;

  // Bins whose centers lie within neighbor_radius_factor · typical_spacing() of ω_j, without j
  // itself, nearest first; precomputed at construction. In the equatorial belt that is exactly
  // the 8 pixels touching the rhombus; in the polar caps, where pixels stretch along the
  // meridians, 6 or 7 of them (the farther diagonal ones drop out). 1.5 would lose the two
  // same-ring corner neighbors on the equator (1.54 spacings away); the next centers beyond
  // are 2 spacings away.
  static constexpr double neighbor_radius_factor = 1.6;
  std::span<const uint16_t> neighbors(int bin) const;

  // Calls visit(bin, angle) for every bin whose center is within `max_angle` radians of the
  // unit vector `center`; touches only the rings whose latitude allows it.
  void for_each_bin_within(const glm::dvec3& center, double max_angle,
                           const std::function<void(int bin, double angle)>& visit) const;

  // Ring layout (rings 1..4·Nside−1 from north to south): first bin and bin count.
  int ring_first_bin(int ring) const;
  int ring_bin_count(int ring) const;
  // cos θ of the ring's centers.
  double ring_z(int ring) const;

 private:
  // HEALPix pix2ang: the center of a bin as (z = cos θ, φ).
  void bin_center(int bin, double& z, double& phi) const;

  int nside_;
  int bin_count_;
  int polar_cap_bins_;  // bins in the north cap: 2·Nside·(Nside−1)
  std::vector<glm::vec3> directions_;
  std::vector<uint32_t> neighbor_offsets_;  // bin_count_ + 1 entries into neighbor_bins_
  std::vector<uint16_t> neighbor_bins_;
};

}  // namespace bakegi::antiradiance
