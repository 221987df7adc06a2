// Weighted least squares of a plane over scattered samples, as an equivalent kernel: fitting
// f(d) = a + b·d (d: a sample's offset in the tangent plane) with weights w_j, the fitted
// value at d = 0 is a = Σ_j l_j y_j for every quantity y measured at the samples, so the
// l_j are computed once and applied to R, G and B (and Σ l_j² v_j is a's variance for
// independent samples of variance v_j). Unlike the weighted mean it has no bias where the
// value changes linearly across the neighbourhood (a gradient, or a point at the rim of a
// surface whose neighbours all lie on one side).
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace bakegi {

// Writes l_j (one per sample) into `kernel`, and when `slope_kernel` is given the kernel of
// the fitted slope b likewise (b = Σ_j s_j y_j). Falls back to the weighted mean, l_j =
// w_j / Σw and slope 0, where the offsets do not determine a slope (fewer than 4 samples with
// weight, or nearly all on one line); offsets should be of order 1 (divided by the
// neighbourhood's radius).
inline void local_linear_kernel(std::span<const float> weights,
                                std::span<const glm::vec2> offsets, std::vector<double>& kernel,
                                std::vector<glm::dvec2>* slope_kernel = nullptr) {
  const size_t n = weights.size();
  kernel.assign(n, 0.0);
  if (slope_kernel) slope_kernel->assign(n, glm::dvec2(0.0));
  glm::dmat3 m(0.0);  // Σ w [1 d][1 d]^T
  double total = 0.0;
  size_t weighted = 0;
  for (size_t j = 0; j < n; ++j) {
    const double w = weights[j];
    if (!(w > 0.0)) continue;
    const glm::dvec3 row(1.0, offsets[j].x, offsets[j].y);
    m += w * glm::outerProduct(row, row);
    total += w;
    ++weighted;
  }
  if (!(total > 0.0)) return;
  // det(M) / total³ is scale-free for unit-order offsets: the weighted covariance of the
  // offsets' determinant; below the threshold the slope is not determined.
  const double spread = glm::determinant(m) / (total * total * total);
  if (weighted < 4 || !(spread > 1e-4)) {
    for (size_t j = 0; j < n; ++j) kernel[j] = weights[j] > 0.0f ? weights[j] / total : 0.0;
    return;
  }
  // M is symmetric: its inverse's columns are its rows. Coefficients = M⁻¹ Σ w [1 d] y.
  const glm::dmat3 inverse = glm::inverse(m);
  for (size_t j = 0; j < n; ++j) {
    if (!(weights[j] > 0.0f)) continue;
    const glm::dvec3 row = double(weights[j]) * glm::dvec3(1.0, offsets[j].x, offsets[j].y);
    kernel[j] = glm::dot(inverse[0], row);
    if (slope_kernel) (*slope_kernel)[j] = glm::dvec2(glm::dot(inverse[1], row),
                                                       glm::dot(inverse[2], row));
  }
}

}  // namespace bakegi
