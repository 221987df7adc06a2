// A stratified hemisphere gather and its irradiance gradients (Ward & Heckbert 1992,
// "Irradiance Gradients"), for the irradiance cache (irradiance_cache.h).
//
// Directions are cosine-distributed, θ = asin √u1, φ = 2π u2, so the M × N cells
// [j/M, (j+1)/M) × [k/N, (k+1)/N) of (u1, u2) have equal projected solid angle π/(MN), and
// E/π is the mean of the cells' mean radiance L_jk. Owen-scrambled Sobol' points (util/random.h)
// put exactly 2^m / (MN) of any 2^m >= MN samples into each cell.
//
// Rotation. E(n) = ∫ L max(0, n·ω) dω; turning n by a small rotation vector α changes it by
// α · ∫ L (n × ω) dω, and n × ω = sin θ v(φ) (v: the tangent direction at azimuth φ + π/2). With
// the cosine density that is
//     ∇_r (E/π) = 1/(MN) Σ_jk L_jk tan θ_j v_k        (θ_j, φ_k: the cell's centre),
// and a record turned from n_i to n changes by (n_i × n) · ∇_r.
//
// Translation (section 3 of the paper). Moving the point by δ in the tangent plane shifts
// what a cell sees: a surface at distance r in direction (θ, φ) moves by dθ = -cos θ (δ·u)/r
// and dφ = -(δ·v)/(r sin θ). Across each cell boundary the neighbour's radiance takes over the
// projected solid angle swept, which gives
//     π ∇_t (E/π) = Σ_k u_k Δφ Σ_{j>=1} sin θ_j- cos² θ_j- (L_jk − L_j-1,k) / min(r_jk, r_j-1,k)
//                 + Σ_k v_k- Σ_j (sin θ_j+ − sin θ_j-) (L_jk − L_j,k-1) / min(r_jk, r_j,k-1)
// (θ_j±: the cell's polar bounds; v_k-: perpendicular to the boundary at φ = 2πk/N; r: the
// nearest hit in the cell, as in the paper). The first sum is the paper's; in the second the
// paper has (cos θ_j- − cos θ_j+)/sin θ_j, which the derivation above does not give: the
// analytic test (test_irradiance_gradients.cpp) checks this one.
//
// Noise. A gradient from a few samples per cell is noisy (its noise falls as
// sqrt(cells / samples), the value's as 1/sqrt(samples)), and a record's prediction carries
// it across its reach. Both gradients are linear in the cell means, so their variance v
// follows from the cells' (per channel); each gradient is shrunk by max(0, |g|² − v)/|g|²
// (James and Stein's positive-part estimator, E|g|² being the true |g|² plus v): a gradient
// its noise explains is dropped, one well above it is kept nearly whole.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

struct Frame;

// What one gather says about the irradiance around its point, per colour channel.
struct IrradianceGather {
  glm::vec3 value{0.0f};                     // E/π, the mean radiance of the samples
  std::array<glm::vec3, 3> rotational{};     // per channel: ∇_r (E/π), world space
  std::array<glm::vec3, 3> translational{};  // per channel: ∇_t (E/π), world space, tangent
  // Harmonic mean distance to what the samples hit (S / Σ 1/r; misses add 0), +inf if none.
  float harmonic_distance = 0.0f;
  float luminance_variance_of_mean = 0.0f;  // of `value`, from the samples' spread
  int64_t samples = 0;
  // Per channel: the variance of each gradient (the sum over its components), from the
  // cells' spread; 0 once shrink_gradients() has used it.
  glm::vec3 rotational_noise{0.0f}, translational_noise{0.0f};
  double luminance_sum = 0.0, luminance_squares = 0.0;  // of the samples
};

// The gradients shrunk by their noise (see "Noise" above).
IrradianceGather shrink_gradients(const IrradianceGather& gather);

// The gather of a's and b's samples together (independent samples at the same point, each
// gather stratified on its own): values and gradients weighted by samples, their noise
// likewise (squared weights), harmonic means through their sums. Neither may be shrunk.
IrradianceGather combine_gathers(const IrradianceGather& a, const IrradianceGather& b);

class HemisphereCells {
 public:
  static constexpr int kThetaCells = 8;  // M
  static constexpr int kPhiCells = 32;   // N ≈ π M as in the paper; M N = 2^8
  static constexpr int kCells = kThetaCells * kPhiCells;

  // The local direction (z = normal) of the numbers (u1, u2).
  static glm::vec3 local_direction(float u1, float u2);

  HemisphereCells() : cells_(kCells) {}
  // One sample: the numbers its direction came from, the radiance it brought, and the
  // distance to its hit (+inf for a miss).
  void add(float u1, float u2, const glm::vec3& radiance, float distance);
  // The gather in world space (frame: the point's, as local_direction's directions used),
  // its gradients as measured (shrink_gradients() takes their noise out).
  // Cells without a sample count as the mean of the others (gradients then are rough).
  IrradianceGather estimate(const Frame& frame) const;
  int64_t samples() const { return samples_; }

 private:
  struct Cell {
    glm::dvec3 radiance{0.0};
    glm::dvec3 squares{0.0};
    int64_t samples = 0;
    float nearest = 0.0f;  // set with the first sample
  };
  std::vector<Cell> cells_;
  int64_t samples_ = 0;
  glm::dvec3 total_squares_{0.0};
  double inverse_distance_sum_ = 0.0;
  double luminance_sum_ = 0.0, luminance_squares_ = 0.0;
};

}  // namespace bakegi
