// The Owen-scrambled Sobol' sequence (util/owen_sobol.h): Sobol's first two dimensions as
// published (van der Corput; direction numbers of x + 1), and the two properties scrambling
// and shuffling must keep: every power-of-two prefix (and every aligned block) is a
// (0, m, 2)-net, and a point is uniform over random seeds. The convergence of estimates
// made with it is tested at the level of the path tracer's streams (test_sample_streams).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "util/owen_sobol.h"
#include "util/pcg32.h"

namespace bakegi {
namespace {

TEST(OwenSobol, DimensionZeroIsVanDerCorput) {
  // 0, 1/2, 1/4, 3/4, 1/8, 5/8, 3/8, 7/8: the binary digits of the index mirrored.
  const double expected[] = {0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875};
  for (uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(double(sobol_dimension0(i)) * 0x1p-32, expected[i]) << i;
  }
  EXPECT_EQ(sobol_dimension0(0x80000000u), 1u);
  EXPECT_EQ(reverse_bits(0x12345678u), 0x1E6A2C48u);
}

TEST(OwenSobol, DimensionOneMatchesTheDirectionNumbersOfXPlusOne) {
  // Bratley and Fox's recurrence for the primitive polynomial x + 1 (degree 1, m_1 = 1):
  // m_k = 2 m_{k-1} xor m_{k-1}; direction number v_k = m_k / 2^k; point = xor of the v_k
  // of the index's set bits. The first m_k: 1, 3, 5, 15, 17, 51.
  uint32_t direction[32];
  uint64_t m = 1;
  for (int k = 1; k <= 32; ++k) {
    if (k > 1) m = (2 * m) ^ m;
    direction[k - 1] = uint32_t(m << (32 - k));
  }
  EXPECT_EQ(direction[1], 0xC0000000u);  // m_2 = 3
  EXPECT_EQ(direction[4], 0x88000000u);  // m_5 = 17
  auto reference = [&](uint32_t index) {
    uint32_t x = 0;
    for (int k = 0; k < 32; ++k) {
      if ((index >> k) & 1u) x ^= direction[k];
    }
    return x;
  };
  for (uint32_t i = 0; i < 4096; ++i) ASSERT_EQ(sobol_dimension1(i), reference(i)) << i;
  Pcg32 rng(11, 5);
  for (int n = 0; n < 4096; ++n) {
    const uint32_t i = rng.next_uint();
    ASSERT_EQ(sobol_dimension1(i), reference(i)) << i;
  }
  // Its first points: 0, 1/2, 3/4, 1/4.
  EXPECT_EQ(sobol_dimension1(2), 0xC0000000u);
  EXPECT_EQ(sobol_dimension1(3), 0x40000000u);
}

TEST(OwenSobol, PointsFollowTheirDefinition) {
  // owen_sobol_point leaves out mirrorings that cancel; it must equal the composition.
  Pcg32 rng(3, 8);
  for (int n = 0; n < 100000; ++n) {
    const uint32_t index = n < 1000 ? uint32_t(n) : rng.next_uint();
    const OwenSobolSeeds seeds{rng.next_uint(), rng.next_uint(), rng.next_uint()};
    const uint32_t shuffled = nested_uniform_scramble(index, seeds.index);
    const SobolPoint p = owen_sobol_point(index, seeds);
    ASSERT_EQ(p.x, nested_uniform_scramble(sobol_dimension0(shuffled), seeds.x)) << index;
    ASSERT_EQ(p.y, nested_uniform_scramble(sobol_dimension1(shuffled), seeds.y)) << index;
  }
}

// Whether points [first, first + 2^m) of the sequence of `seeds` have exactly one point in
// each elementary interval of area 2^-m, of all m + 1 shapes 2^-a x 2^-(m - a).
::testing::AssertionResult is_net(const OwenSobolSeeds& seeds, uint32_t first, int m) {
  const uint32_t count = 1u << m;
  std::vector<SobolPoint> points(count);
  for (uint32_t i = 0; i < count; ++i) points[i] = owen_sobol_point(first + i, seeds);
  for (int a = 0; a <= m; ++a) {
    std::vector<int> occupied(count, 0);
    for (const SobolPoint& p : points) {
      const uint64_t column = a == 0 ? 0 : p.x >> (32 - a);
      const uint64_t row = a == m ? 0 : p.y >> (32 - (m - a));
      if (++occupied[(column << (m - a)) | row] > 1) {
        return ::testing::AssertionFailure()
               << "two points in one 2^-" << a << " x 2^-" << (m - a) << " interval ("
               << count << " points from " << first << ")";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(OwenSobol, EveryPowerOfTwoPrefixAndAlignedBlockIsANet) {
  Pcg32 rng(2020, 9);
  for (int trial = 0; trial < 8; ++trial) {
    const OwenSobolSeeds seeds{rng.next_uint(), rng.next_uint(), rng.next_uint()};
    for (int m = 0; m <= 12; ++m) EXPECT_TRUE(is_net(seeds, 0, m)) << "trial " << trial;
    // A block [j 2^m, (j + 1) 2^m): what a sample offset that is a multiple of 2^m gets.
    EXPECT_TRUE(is_net(seeds, 5u << 8, 8));
    EXPECT_TRUE(is_net(seeds, 0xFFFFF000u, 12));  // the last block of the index range
  }
  EXPECT_TRUE(is_net(OwenSobolSeeds{0, 0, 0}, 0, 12));
}

TEST(OwenSobol, ANetCheckCatchesMisplacedPoints) {
  // The check itself can fail: 256 points that are not an aligned block, [3, 259), are
  // 253 points of one net and 3 of the next.
  const OwenSobolSeeds seeds{1, 2, 3};
  EXPECT_FALSE(is_net(seeds, 3, 8));
}

TEST(OwenSobol, ScramblesChangeEveryPointAndDigit) {
  // Not the identity: over seeds, each of the first 16 digits of a coordinate is flipped
  // about half the time (binomial, 4096 seeds: 2048 +- 32; 5 sigma = 160).
  Pcg32 rng(77, 1);
  for (uint32_t index : {0u, 1u, 6u, 1000u}) {
    int flips_x[16] = {}, flips_y[16] = {};
    const SobolPoint plain = owen_sobol_point(index, OwenSobolSeeds{0, 0, 0});
    for (int s = 0; s < 4096; ++s) {
      const OwenSobolSeeds seeds{rng.next_uint(), rng.next_uint(), rng.next_uint()};
      const SobolPoint p = owen_sobol_point(index, seeds);
      for (int d = 0; d < 16; ++d) {
        flips_x[d] += ((p.x ^ plain.x) >> (31 - d)) & 1u;
        flips_y[d] += ((p.y ^ plain.y) >> (31 - d)) & 1u;
      }
    }
    for (int d = 0; d < 16; ++d) {
      EXPECT_NEAR(flips_x[d], 2048, 160) << "index " << index << " digit " << d;
      EXPECT_NEAR(flips_y[d], 2048, 160) << "index " << index << " digit " << d;
    }
  }
}

}  // namespace
}  // namespace bakegi
