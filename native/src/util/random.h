// Deterministic random numbers for Monte Carlo estimators. Every sample of every bake point
// gets its own PCG32 stream, seeded by hashing (seed, point index, sample index), so:
//  - results do not depend on thread count or scheduling;
//  - sample j of a point is the same whatever the total sample count, so N samples and 2N
//    samples share their first N (progressive: more samples = same estimator, less noise);
//  - a sample offset shifts the sample index, so a reference made in chunks with offsets
//    0, N, 2N, ... averages exactly to one run.
#pragma once

#include <cstdint>

namespace bakegi {

// SplitMix64's finalizer: a bijective 64-bit mix with full avalanche.
inline uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// O'Neill's PCG32 (XSH-RR): small state, good statistical quality, cheap to seed.
class Pcg32 {
 public:
  Pcg32(uint64_t initial_state, uint64_t stream) : state_(0), increment_((stream << 1u) | 1u) {
    next_uint();
    state_ += initial_state;
    next_uint();
  }

  uint32_t next_uint() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rotation = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rotation) | (xorshifted << ((32u - rotation) & 31u));
  }

  // Uniform in [0, 1): 24 random bits, so 1 is never returned.
  float next_float() { return static_cast<float>(next_uint() >> 8) * 0x1p-24f; }

 private:
  uint64_t state_;
  uint64_t increment_;
};

// The stream of one sample of one bake point.
inline Pcg32 sample_stream(uint64_t seed, uint64_t point, uint64_t sample) {
  const uint64_t key = mix64(mix64(mix64(seed) ^ point) ^ (sample * 0xD1B54A32D192ED03ull));
  return Pcg32(key, mix64(key ^ 0x6A09E667F3BCC909ull));
}

}  // namespace bakegi
