// The project's one error metric for comparing a bake with a reference (DESIGN.md,
// "Measuring"): relative RMSE over bake points, luminance-weighted,
//
//   e = sqrt( sum_i sum_c w_c (v_ic - r_ic)^2  /  sum_i sum_c w_c r_ic^2 )
//
// with Rec. 709 luminance weights w = (0.2126, 0.7152, 0.0722). Weighting the squared
// differences per channel (rather than comparing luminances) keeps chroma errors visible
// while letting green, which the eye sees best, count most. e = 0.01 reads as "1% RMS".
// The CLI (`bakegi sweep`, `bakegi compare`) and the tests use this function; Python
// scripts call the CLI instead of re-implementing it.
#pragma once

#include <cstddef>
#include <optional>

namespace bakegi {

inline constexpr float kLuminanceWeights[3] = {0.2126f, 0.7152f, 0.0722f};

// values and reference hold 3 * count floats (RGB per bake point). Returns nullopt when
// the error is undefined: count == 0, a non-finite entry, or a reference that is zero
// everywhere.
std::optional<double> relative_rmse_luminance(const float* values, const float* reference,
                                              size_t count);

}  // namespace bakegi
