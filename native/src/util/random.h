// Deterministic random numbers for Monte Carlo estimators. Every sample of every bake point
// gets its own stream, seeded by hashing (seed, point index, sample index), so:
//  - results do not depend on thread count or scheduling;
//  - sample j of a point is the same whatever the total sample count, so N samples and 2N
//    samples share their first N (progressive: more samples = same estimator, less noise);
//  - a sample offset shifts the sample index, so a reference made in chunks with offsets
//    0, N, 2N, ... averages exactly to one run.
// The streams of the point-sampling loop (solvers/point_sampling.h: the path tracer, method
// direct) begin with randomized quasi-Monte Carlo numbers (sobol_sample_stream): the samples
// of a point stratify the first dimensions of its paths together. Other users keep plain
// PCG32 streams (sample_stream).
#pragma once

#include <array>
#include <cstdint>

#include "util/owen_sobol.h"
#include "util/pcg32.h"

namespace bakegi {

// The random numbers of one Monte Carlo sample: an optional prefix of given numbers (the
// quasi-random ones), then PCG32. Every number is uniform on its own either way; the prefix
// only correlates the samples of one point with each other, which keeps every estimate
// unbiased. Without a prefix it draws exactly the numbers of its Pcg32.
class RandomStream {
 public:
  static constexpr int kMaxPrefix = 6;

  RandomStream(uint64_t initial_state, uint64_t stream) : pcg_(initial_state, stream) {}
  explicit RandomStream(const Pcg32& pcg) : pcg_(pcg) {}
  // The first prefix.size() <= kMaxPrefix draws return `prefix`, the later ones pcg's.
  template <size_t N>
  RandomStream(const Pcg32& pcg, const std::array<uint32_t, N>& prefix)
      : pcg_(pcg), prefix_size_(N) {
    static_assert(N <= kMaxPrefix);
    for (size_t k = 0; k < N; ++k) prefix_[k] = prefix[k];
  }

  uint32_t next_uint() { return next_ < prefix_size_ ? prefix_[next_++] : pcg_.next_uint(); }

  // Uniform in [0, 1): 24 bits, so 1 is never returned.
  float next_float() { return unit_float(next_uint()); }

 private:
  Pcg32 pcg_;
  uint32_t prefix_[kMaxPrefix] = {};
  uint8_t prefix_size_ = 0;
  uint8_t next_ = 0;
};

// The PCG32 engine of one sample of one bake point.
inline Pcg32 sample_pcg(uint64_t seed, uint64_t point, uint64_t sample) {
  const uint64_t key = mix64(mix64(mix64(seed) ^ point) ^ (sample * 0xD1B54A32D192ED03ull));
  return Pcg32(key, mix64(key ^ 0x6A09E667F3BCC909ull));
}

// The stream of one sample of one bake point: PCG32 only, independent between samples (the
// error probes' sample variance relies on that).
inline RandomStream sample_stream(uint64_t seed, uint64_t point, uint64_t sample) {
  return RandomStream(sample_pcg(seed, point, sample));
}

// How many numbers of a sobol_sample_stream are quasi-random: three pairs, which a path
// spends on its first direction, the first hit's light sample and its next direction.
inline constexpr int kSobolDraws = 6;

// The randomization of pair `pair` of point `point`'s sequence. Sample indices past 2^32
// start a new randomization every 2^32 samples (the sequence has 32-bit indices).
inline OwenSobolSeeds sobol_seeds(uint64_t seed, uint64_t point, int pair, uint64_t sample) {
  constexpr uint64_t kSalt = 0x50B0150B0150B01ull;  // apart from sample_pcg's keys
  const uint64_t key =
      mix64(mix64(mix64(seed ^ kSalt) ^ point) ^ (uint64_t(pair) | ((sample >> 32) << 8)));
  const uint64_t more = mix64(key);
  return {uint32_t(key), uint32_t(key >> 32), uint32_t(more)};
}

// sample_stream's numbers after kSobolDraws numbers of Owen-scrambled Sobol' points (pairs
// padded with independent shuffles): as random as sample_stream's one sample at a time, but
// any 2^k samples of a point starting at a multiple of 2^k stratify each pair as a net.
inline RandomStream sobol_sample_stream(uint64_t seed, uint64_t point, uint64_t sample) {
  std::array<uint32_t, kSobolDraws> prefix;
  for (int pair = 0; pair < kSobolDraws / 2; ++pair) {
    const OwenSobolSeeds seeds = sobol_seeds(seed, point, pair, sample);
    const SobolPoint p = owen_sobol_point(uint32_t(sample), seeds);
    prefix[2 * pair] = p.x;
    prefix[2 * pair + 1] = p.y;
  }
  return RandomStream(sample_pcg(seed, point, sample), prefix);
}

}  // namespace bakegi
