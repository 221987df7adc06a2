// Owen-scrambled Sobol' points in two dimensions (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4)): the quasi-random first numbers of every path (util/random.h).
//
// The first two dimensions of Sobol's sequence form a (0, 2)-sequence in base 2: every
// aligned block of 2^m consecutive points is a (0, m, 2)-net, one point in each elementary
// interval [a 2^-i, (a + 1) 2^-i) x [b 2^-j, (b + 1) 2^-j) with i + j = m. Nested uniform
// (Owen) scrambling flips each binary digit of a coordinate by a random function of the
// digits before it: the nets stay nets and every point becomes uniform on [0, 1)^2, so
// estimates stay unbiased and different seeds give independent randomizations. The index
// is shuffled by the same kind of scramble (each digit flipped by a function of the more
// significant ones), which maps [0, 2^m) onto one aligned block of 2^m indices: every
// power-of-two prefix of the shuffled sequence is still a net, and sequences that share an
// index but not the shuffle seed are decorrelated (how further pairs of dimensions are
// padded). The scrambles are hashes, not stored permutations: a point costs a few dozen
// integer operations.
#pragma once

#include <cstdint>

namespace bakegi {

// Bit k of x moved to bit 31 - k (GCC and Clang swap the bytes in one instruction).
inline uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  return __builtin_bswap32(x);
}

// Coordinates are 32-bit binary fractions (value / 2^32), most significant digit first.

// Sobol's dimension 0: the van der Corput sequence, the index's bits mirrored.
inline uint32_t sobol_dimension0(uint32_t index) { return reverse_bits(index); }

// Sobol's dimension 1 (primitive polynomial x + 1): index bit k contributes the direction
// number v_k, whose binary digit j + 1 is C(k, j) mod 2 (Pascal's triangle: m_k = 1, 3, 5,
// 15, 17, ...). By Lucas' theorem C(k, j) is odd iff the bits of j are a subset of those of
// k, so digit j + 1 of the point is the parity of the index bits k that contain j: a
// superset transform over the five bits of the bit position, one shift per bit. This
// returns the digits mirrored (bit j = digit j + 1), as the scramble below wants them.
inline uint32_t sobol_dimension1_mirrored(uint32_t index) {
  uint32_t z = index;
  z ^= (z >> 1) & 0x55555555u;
  z ^= (z >> 2) & 0x33333333u;
  z ^= (z >> 4) & 0x0F0F0F0Fu;
  z ^= (z >> 8) & 0x00FF00FFu;
  z ^= (z >> 16) & 0x0000FFFFu;
  return z;
}

inline uint32_t sobol_dimension1(uint32_t index) {
  return reverse_bits(sobol_dimension1_mirrored(index));
}

// Laine and Karras' hash with Burley's constants: bit k of the result is bit k of x flipped
// by a function of the lower bits of x and of the seed (adding, and xoring with a multiple
// by an even number, never move information downwards), and by seed bit k itself, so over
// random seeds every bit is flipped with probability 1/2 whatever the lower bits are.
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Nested uniform scrambling of a binary fraction: the hash above on the mirrored digits, so
// each digit is flipped by a function of the more significant ones.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// The seeds of one randomization: the index shuffle and the scramble of each coordinate.
struct OwenSobolSeeds {
  uint32_t index, x, y;
};

struct SobolPoint {
  uint32_t x, y;  // binary fractions
};

// Point `index` of the shuffled, scrambled sequence of `seeds`, by definition
//   shuffled = nested_uniform_scramble(index, seeds.index),
//   x = nested_uniform_scramble(sobol_dimension0(shuffled), seeds.x),
//   y = nested_uniform_scramble(sobol_dimension1(shuffled), seeds.y),
// without the mirrorings that cancel (half of them).
inline SobolPoint owen_sobol_point(uint32_t index, const OwenSobolSeeds& seeds) {
  const uint32_t shuffled = nested_uniform_scramble(index, seeds.index);
  return {reverse_bits(laine_karras_permutation(shuffled, seeds.x)),
          reverse_bits(laine_karras_permutation(sobol_dimension1_mirrored(shuffled), seeds.y))};
}

}  // namespace bakegi
