// The random number engine of every Monte Carlo estimator (util/random.h hands it out per
// sample) and the 64-bit mix its seeds are hashed with.
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

// Uniform in [0, 1) from the top 24 bits of a 32-bit number, so 1 is never returned.
inline float unit_float(uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1p-24f; }

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

  float next_float() { return unit_float(next_uint()); }

 private:
  uint64_t state_;
  uint64_t increment_;
};

}  // namespace bakegi
