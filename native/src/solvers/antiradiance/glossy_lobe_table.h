// The Phong lobe (scene/phong_lobe.h) discretized on the directional bins, for the glossy
// branch of the local pass (Eq. 18 with f = ρ_d/π + f_g).
//
// A patch's lobe for an outgoing bin j is centered at the mirror image of ω_j, which falls
// anywhere inside some bin c; its axis depends on the patch normal, so tables cannot be per
// patch. The table holds, per center bin c, the distribution of the lobe's directions over
// the bins when its axis is uniform inside bin c: a sparse list of (bin, weight), weights
// summing to 1. This is the lobe integrated over each bin (not sampled at bin centers), so a
// lobe narrower than a bin (n ≳ 50 at 192 bins) lands fully in the bins it overlaps instead
// of missing them or spiking; it is at least one bin wide. It is built by deterministic
// sampling (32 axes in bin c × 64 lobe directions each) when the lobe is within two bin
// spacings, and from cos^n at the bin centers for wider lobes, where that is accurate and
// sampling would be noisy.
//
// With the table the local pass normalizes per outgoing bin (the discrete directional albedo
// equals the analytic A(μ) of directional_albedo(), so a uniform field is reflected exactly)
// and per patch (the reflected flux equals Σ_l A(μ_l) E_l, so no field gains energy); see
// local_pass.h.
//
// Tables are shared: table_for() builds each (exponent, bin count) once per process and
// keeps it (memory_bytes(): 24 kB at 192 bins for a near mirror, up to m²/2 entries for a
// lobe as wide as a hemisphere).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "solvers/antiradiance/directional_bins.h"

namespace bakegi::antiradiance {

struct LobeWeight {
  uint16_t bin;
  float weight;
};

class GlossyLobeTable {
 public:
  GlossyLobeTable(const DirectionalBins& bins, float exponent);

  // The shared table for these bins and exponent (thread-safe; built on first use).
  static std::shared_ptr<const GlossyLobeTable> table_for(const DirectionalBins& bins,
                                                          float exponent);

  float exponent() const { return exponent_; }
  int bin_count() const { return bin_count_; }
  // The lobe whose axis lies in bin `center`: weights sum to 1, largest first.
  std::span<const LobeWeight> lobe(int center) const {
    return {weights_.data() + offsets_[size_t(center)],
            offsets_[size_t(center) + 1] - offsets_[size_t(center)]};
  }
  // A(μ) / ρ_g of phong_directional_albedo(), interpolated from 257 samples in μ (error below
  // 1e-3 for any exponent: A is smooth in μ).
  float directional_albedo(float mu) const;
  size_t memory_bytes() const;

 private:
  float exponent_;
  int bin_count_;
  std::vector<uint32_t> offsets_;
  std::vector<LobeWeight> weights_;
  std::vector<float> albedo_;  // A at μ = k / (size − 1)
};

struct Patch;

// The lobe table of each patch's exponent (nullptr for patches without a lobe), each table
// looked up once; `keep_alive` holds them. Used by the local pass and the direct
// initialization.
std::vector<const GlossyLobeTable*> glossy_tables_for_patches(
    const std::vector<Patch>& patches, const DirectionalBins& bins,
    std::vector<std::shared_ptr<const GlossyLobeTable>>& keep_alive);

}  // namespace bakegi::antiradiance
