// The random streams of Monte Carlo samples (util/random.h). Plain streams draw exactly their
// PCG32 engine's numbers (the solvers that use them are unchanged). The path tracer's
// streams begin with three pairs of Owen-scrambled Sobol' points, which must be
// deterministic, nets over every aligned power-of-two block of a point's samples, padded
// (pairs independent of each other), uniform over seeds (so estimates stay unbiased), and
// converge faster than independent samples: RMSE about N^-1.5 for a smooth integrand and
// variance about N^-1.5 for a discontinuous one, where independent samples give N^-0.5 and
// N^-1 (Owen 1997, 1998).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "scene/bake_points.h"
#include "solvers/point_sampling.h"
#include "util/job_context.h"
#include "util/random.h"
#include "util/sampling.h"

namespace bakegi {
namespace {

// The first kSobolDraws numbers of a stream.
std::array<float, kSobolDraws> prefix_of(RandomStream stream) {
  std::array<float, kSobolDraws> u;
  for (float& v : u) v = stream.next_float();
  return u;
}

TEST(SampleStreams, PlainStreamsDrawTheirPcgNumbers) {
  for (uint64_t sample : {0ull, 1ull, 99ull, 1ull << 35}) {
    RandomStream stream = sample_stream(42, 7, sample);
    Pcg32 pcg = sample_pcg(42, 7, sample);
    for (int k = 0; k < 20; ++k) ASSERT_EQ(stream.next_uint(), pcg.next_uint());
    for (int k = 0; k < 20; ++k) ASSERT_EQ(stream.next_float(), pcg.next_float());
  }
  RandomStream stream(7, 3);
  Pcg32 pcg(7, 3);
  for (int k = 0; k < 20; ++k) ASSERT_EQ(stream.next_float(), pcg.next_float());
}

TEST(SampleStreams, SobolStreamsAreDeterministicThenContinueWithPcg) {
  RandomStream a = sobol_sample_stream(3, 10, 77), b = sobol_sample_stream(3, 10, 77);
  Pcg32 pcg = sample_pcg(3, 10, 77);
  for (int pair = 0; pair < kSobolDraws / 2; ++pair) {
    const SobolPoint p = owen_sobol_point(77, sobol_seeds(3, 10, pair, 77));
    const uint32_t x = a.next_uint(), y = a.next_uint();
    EXPECT_EQ(x, p.x);
    EXPECT_EQ(y, p.y);
    EXPECT_EQ(b.next_float(), unit_float(x));
    EXPECT_EQ(b.next_float(), unit_float(y));
  }
  for (int k = 0; k < 20; ++k) {
    const uint32_t expected = pcg.next_uint();
    EXPECT_EQ(a.next_uint(), expected);
    EXPECT_EQ(b.next_float(), unit_float(expected));
  }
  // Another seed, point or sample gives other numbers.
  const auto base = prefix_of(sobol_sample_stream(3, 10, 77));
  EXPECT_NE(prefix_of(sobol_sample_stream(4, 10, 77)), base);
  EXPECT_NE(prefix_of(sobol_sample_stream(3, 11, 77)), base);
  EXPECT_NE(prefix_of(sobol_sample_stream(3, 10, 78)), base);
  // Past 2^32 samples the sequence starts a new randomization instead of repeating.
  EXPECT_NE(prefix_of(sobol_sample_stream(3, 10, 77 + (1ull << 32))), base);
}

// Whether each pair of the prefixes of samples [first, first + 2^m) of a point has exactly
// one point in every elementary interval 2^-a x 2^-(m - a).
::testing::AssertionResult pairs_are_nets(uint64_t seed, uint64_t point, uint64_t first,
                                          int m) {
  const int count = 1 << m;
  std::vector<std::array<float, kSobolDraws>> prefixes;
  for (int s = 0; s < count; ++s) {
    prefixes.push_back(prefix_of(sobol_sample_stream(seed, point, first + s)));
  }
  for (int pair = 0; pair < kSobolDraws / 2; ++pair) {
    for (int a = 0; a <= m; ++a) {
      std::vector<int> occupied(count, 0);
      for (const auto& u : prefixes) {
        // Exact: u is a multiple of 2^-24 and a, m - a <= 24.
        const int column = int(u[2 * pair] * float(1 << a));
        const int row = int(u[2 * pair + 1] * float(1 << (m - a)));
        if (++occupied[(column << (m - a)) | row] > 1) {
          return ::testing::AssertionFailure()
                 << "pair " << pair << ": two samples in one 2^-" << a << " x 2^-" << (m - a)
                 << " interval (seed " << seed << ", point " << point << ", samples from "
                 << first << ")";
        }
      }
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(SampleStreams, EachPairOfAPointsSamplesIsANetOverPowerOfTwoBlocks) {
  for (uint64_t seed : {0ull, 1ull, 12345ull}) {
    for (uint64_t point : {0ull, 7ull, 1ull << 20}) {
      for (int m = 0; m <= 10; ++m) EXPECT_TRUE(pairs_are_nets(seed, point, 0, m));
      // A chunk of a reference made with sample_offset = 3 x 256.
      EXPECT_TRUE(pairs_are_nets(seed, point, 3 * 256, 8));
    }
  }
  // The check can fail: a block that is not aligned mixes two nets.
  EXPECT_FALSE(pairs_are_nets(0, 0, 100, 8));
}

TEST(SampleStreams, PairsArePadded) {
  // Pairs of one point share the sample index; each has its own index shuffle, so one pair's
  // coordinates say nothing about another's. Over 4096 samples in a 64 x 64 grid, two
  // independent coordinates occupy 4096 (1 - (1 - 1/4096)^4096) = 2589 +- ~30 cells; pairs
  // sharing the shuffle would be a bijection of strata at this level: 64 cells.
  const int count = 4096;
  std::vector<std::array<float, kSobolDraws>> prefixes;
  for (int s = 0; s < count; ++s) prefixes.push_back(prefix_of(sobol_sample_stream(5, 3, s)));
  for (int i = 0; i < kSobolDraws; ++i) {
    for (int j = (i / 2 + 1) * 2; j < kSobolDraws; ++j) {
      std::vector<char> occupied(64 * 64, 0);
      for (const auto& u : prefixes) occupied[int(u[i] * 64.0f) * 64 + int(u[j] * 64.0f)] = 1;
      int cells = 0;
      for (char c : occupied) cells += c;
      EXPECT_GT(cells, 2400) << "draws " << i << " and " << j;
      EXPECT_LT(cells, 2780) << "draws " << i << " and " << j;
    }
  }
}

TEST(SampleStreams, EachSampleIsUniformOverSeeds) {
  // Sample j's pair, over 65536 seeds, in 16 x 16 cells: chi-square with 255 degrees of
  // freedom, mean 255 and standard deviation sqrt(510) = 22.6; fail above 5 sigma (368).
  // Without the scramble sample 0 would always be (0, 0).
  for (uint64_t sample : {0ull, 5ull, 1023ull}) {
    for (int pair = 0; pair < kSobolDraws / 2; ++pair) {
      std::vector<int> cells(256, 0);
      const int seeds = 65536;
      for (int seed = 0; seed < seeds; ++seed) {
        const auto u = prefix_of(sobol_sample_stream(uint64_t(seed), 9, sample));
        ++cells[int(u[2 * pair] * 16.0f) * 16 + int(u[2 * pair + 1] * 16.0f)];
      }
      const double expected = seeds / 256.0;
      double chi2 = 0.0;
      for (int c : cells) chi2 += (c - expected) * (c - expected) / expected;
      EXPECT_LT(chi2, 368.0) << "sample " << sample << " pair " << pair;
    }
  }
}

// The mean of f over samples [0, n) of point `point` with `seed`, on draws (2 pair, 2 pair + 1).
using StreamMaker = std::function<RandomStream(uint64_t seed, uint64_t point, uint64_t sample)>;
double estimate(const StreamMaker& make, const std::function<double(float, float)>& f,
                uint64_t seed, uint64_t point, int pair, int n) {
  double sum = 0.0;
  for (int s = 0; s < n; ++s) {
    RandomStream stream = make(seed, point, uint64_t(s));
    for (int k = 0; k < 2 * pair; ++k) stream.next_float();
    const float u = stream.next_float(), v = stream.next_float();
    sum += f(u, v);
  }
  return sum / n;
}

struct Spread {
  double mean, rmse, standard_error;  // rmse against the exact value, over randomizations
};

// Estimates of `exact` with n samples at `randomizations` independent seeds.
Spread spread(const StreamMaker& make, const std::function<double(float, float)>& f,
              double exact, int pair, int n, int randomizations) {
  double sum = 0.0, sum2 = 0.0, squared_error = 0.0;
  for (int r = 0; r < randomizations; ++r) {
    const double e = estimate(make, f, uint64_t(r) * 7919u + 1u, 4, pair, n);
    sum += e;
    sum2 += e * e;
    squared_error += (e - exact) * (e - exact);
  }
  const double mean = sum / randomizations;
  const double variance = std::max(0.0, sum2 / randomizations - mean * mean);
  return {mean, std::sqrt(squared_error / randomizations),
          std::sqrt(variance / (randomizations - 1))};
}

const StreamMaker kSobol = [](uint64_t seed, uint64_t point, uint64_t sample) {
  return sobol_sample_stream(seed, point, sample);
};
const StreamMaker kIndependent = [](uint64_t seed, uint64_t point, uint64_t sample) {
  return sample_stream(seed, point, sample);
};

// Smooth and not separable: the integral of u e^(u v) over the unit square is e - 2.
double smooth(float u, float v) { return double(u) * std::exp(double(u) * double(v)); }
const double kSmoothIntegral = std::exp(1.0) - 2.0;

TEST(SampleStreams, SobolEstimatesAreUnbiased) {
  // The mean of 4096 independent estimates is within 5 standard errors of the integral
  // (plus 1e-6 for 24-bit numbers), for every pair and for 1 sample as for 16.
  for (int pair = 0; pair < kSobolDraws / 2; ++pair) {
    for (int n : {1, 16}) {
      const Spread s = spread(kSobol, smooth, kSmoothIntegral, pair, n, 4096);
      EXPECT_NEAR(s.mean, kSmoothIntegral, 5.0 * s.standard_error + 1e-6)
          << "pair " << pair << ", " << n << " samples";
    }
  }
}

TEST(SampleStreams, SmoothIntegrandRmseIsTenTimesBelowIndependentSamples) {
  // Owen: for a smooth integrand the scrambled-net RMSE falls as N^-1.5 (up to logs), so at
  // N = 256 it is ~N times below sigma / sqrt(N): asking for 10x leaves room for constants
  // and the RMSEs' own noise (256 randomizations: +-5%). Samples that lost their
  // stratification (a broken scramble or shuffle) would give about 1x.
  const int n = 256, randomizations = 256;
  for (int pair = 0; pair < kSobolDraws / 2; ++pair) {
    const double sobol = spread(kSobol, smooth, kSmoothIntegral, pair, n, randomizations).rmse;
    const double independent =
        spread(kIndependent, smooth, kSmoothIntegral, pair, n, randomizations).rmse;
    std::printf("pair %d, %d samples: RMSE independent %.3g, Sobol %.3g (%.0fx)\n", pair, n,
                independent, sobol, independent / sobol);
    EXPECT_GT(independent / sobol, 10.0) << "pair " << pair;
  }
}

// Least-squares slope of log y against log x.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0.0, my = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += std::log(x[i]) / x.size();
    my += std::log(y[i]) / y.size();
  }
  double sxy = 0.0, sxx = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
    sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
  }
  return sxy / sxx;
}

TEST(SampleStreams, DiscontinuousIntegrandVarianceFallsFasterThanOneOverN) {
  // The cosine-weighted hemisphere's share of directions with x + y / 2 > 0.3, as the path
  // tracer draws them (sample_cosine_hemisphere). Projected to the unit disk the directions
  // are uniform, so it is the disk segment beyond the line at distance h = 0.3 / sqrt(1.25):
  // (acos h - h sqrt(1 - h^2)) / pi. An indicator has a discontinuity along a curve, where
  // scrambled nets give a variance of about N^-1.5 and independent samples N^-1. Slopes fitted
  // over N = 16..1024 with 512 randomizations each are good to about +-0.05.
  const double h = 0.3 / std::sqrt(1.25);
  const double exact = (std::acos(h) - h * std::sqrt(1.0 - h * h)) / M_PI;
  auto indicator = [](float u, float v) {
    const glm::vec3 d = sample_cosine_hemisphere(u, v);
    return d.x + 0.5f * d.y > 0.3f ? 1.0 : 0.0;
  };
  std::vector<double> counts, sobol, independent;
  for (int n = 16; n <= 1024; n *= 4) {
    counts.push_back(n);
    const double s = spread(kSobol, indicator, exact, 0, n, 512).rmse;
    const double i = spread(kIndependent, indicator, exact, 0, n, 512).rmse;
    sobol.push_back(s * s);
    independent.push_back(i * i);
    std::printf("%4d samples: variance independent %.3g, Sobol %.3g\n", n, i * i, s * s);
  }
  const double sobol_slope = log_slope(counts, sobol);
  const double independent_slope = log_slope(counts, independent);
  std::printf("variance slopes: independent %.2f, Sobol %.2f\n", independent_slope,
              sobol_slope);
  EXPECT_LT(sobol_slope, -1.3);
  EXPECT_NEAR(independent_slope, -1.0, 0.15);  // the same fit sees plain Monte Carlo
}

TEST(SampleStreams, PointSamplingGivesEverySampleItsSobolStream) {
  // estimate_at_points averages sample j of point i on sobol_sample_stream(seed, i,
  // offset + j), which depends on nothing else: not on the total count, nor on threads.
  BakePoints points;
  for (int i = 0; i < 40; ++i) {
    points.positions.push_back(glm::vec3(float(i), 0.0f, 0.0f));
    points.normals.push_back(glm::vec3(0.0f, 0.0f, 1.0f));
    points.object_ids.push_back(0);
  }
  const PointSampleEstimator draws = [](const SurfacePoint&, RandomStream& rng, uint64_t&) {
    const float u0 = rng.next_float(), u1 = rng.next_float();
    for (int k = 2; k < kSobolDraws; ++k) rng.next_float();
    return glm::vec3(u0, u1, rng.next_float());
  };
  for (int64_t offset : {0, 16}) {
    for (int64_t samples : {1, 8, 16}) {
      SampleSettings sampling;
      sampling.samples = samples;
      sampling.seed = 31;
      sampling.sample_offset = offset;
      std::vector<glm::vec3> out(points.size());
      JobContext context;
      estimate_at_points(points, out, sampling, draws, context);
      for (size_t i = 0; i < points.size(); ++i) {
        glm::dvec3 sum(0.0);
        for (int64_t s = 0; s < samples; ++s) {
          RandomStream rng = sobol_sample_stream(31, i, uint64_t(offset + s));
          SurfacePoint x{};
          uint64_t rays = 0;
          sum += glm::dvec3(draws(x, rng, rays));
        }
        ASSERT_EQ(out[i], glm::vec3(sum / double(samples))) << "point " << i;
      }
    }
  }
}

}  // namespace
}  // namespace bakegi
