// The spreading filter of §3.1 (Fig. 8) as precomputed tables per cone size (§4.2).
//
// A link whose sender subtends more than one bin from the receiver would put all its energy
// into the one bin of the direction between the centers. Instead, the energy is spread over
// the bins around it with a Gaussian of standard deviation sqrt(4π/m) (the spacing of the bins)
// over a neighborhood the size of the sender's cone. We realize that as the sender's cone (a
// spherical cap of half-angle α around the central bin ω_j, uniformly bright) prefiltered by the
// Gaussian, evaluated at each bin center:
//
//   w_l ∝ ∫_{cap(ω_j, α)} exp(−∠(ω, ω_l)² / 2σ²) dω,   σ = sqrt(4π/m),
//
// normalized so that Σ_l w_l = 1 for every j: the filtered form factor moves the same flux as
// the unfiltered one. For a cone about one bin wide this is the paper's Gaussian over the cone's
// neighborhood; unlike a Gaussian merely truncated at the cone's radius, it keeps spreading a
// wide cone over its whole extent instead of over about 3σ around its center whatever its size.
// The support is cut at α + 2.5σ (beyond it the filtered cap has fallen below ~4% of its peak)
// and renormalized.
//
// Cone sizes are quantized into classes: class 0 is every cone no larger than one bin
// (solid angle ≤ 4π/m), the identity (weight 1 on j, as the paper spreads only wider
// senders); class k ≥ 1 has half-angle α_bin · 2^(k/2) (solid angle about doubling per class),
// up to the first class at or beyond `max_half_angle` (45° by default), which is clamped to it.
// Wider cones use the last class. For each class and central bin the table holds a sparse list
// of (bin, weight), nearest first; the lookup is O(1) by (class, bin).
#pragma once

#include <cstddef>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "solvers/antiradiance/directional_bins.h"

namespace bakegi::antiradiance {

// The bins that receive a spread exchange and their weights (parallel spans, same length).
struct SpreadFilter {
  std::span<const uint16_t> bins;
  std::span<const float> weights;
};

class BinSpreading {
 public:
  static constexpr double default_max_half_angle = std::numbers::pi / 4.0;

  explicit BinSpreading(const DirectionalBins& bins,
                        double max_half_angle = default_max_half_angle);

  int bin_count() const { return bin_count_; }
  // Number of cone classes, the identity class 0 included.
  int class_count() const { return static_cast<int>(half_angles_.size()); }
  // Cone half-angle of class k in radians (class 0: the cone of one bin).
  double class_half_angle(int cone_class) const {
    return half_angles_[static_cast<size_t>(cone_class)];
  }
  // The class for a sender subtending `cone_solid_angle` steradians at the receiver: 0 for at
  // most one bin (and for non-finite input), else the class nearest in log half-angle.
  int class_of(double cone_solid_angle) const;

  // The filter of class `cone_class` around central bin `bin`.
  SpreadFilter filter(int cone_class, int bin) const;

  // Bytes held by the tables (offsets, bin indices and weights of every class).
  size_t memory_bytes() const;

 private:
  struct ClassTable {
    std::vector<uint32_t> offsets;  // bin_count_ + 1 entries
    std::vector<uint16_t> bins;
    std::vector<float> weights;
  };

  int bin_count_;
  double bin_half_angle_;
  std::vector<double> half_angles_;
  std::vector<uint16_t> identity_bins_;  // class 0: bin j → {j}
  float identity_weight_ = 1.0f;
  std::vector<ClassTable> tables_;  // classes 1.., index k − 1
};

}  // namespace bakegi::antiradiance
