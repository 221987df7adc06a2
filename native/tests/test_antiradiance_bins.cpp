// The directional bins of §3.1 (HEALPix ring scheme) and the spreading filter tables of Fig. 8 /
// §4.2: known HEALPix values, exact round trips, equal area by Monte Carlo with binomial
// tolerances, neighbor lists, and the filters' energy preservation, shape and growth with cone.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "solvers/antiradiance/bin_spreading.h"
#include "solvers/antiradiance/directional_bins.h"
#include "util/random.h"

namespace bakegi::antiradiance {
namespace {

constexpr double kPi = std::numbers::pi;

double angle_between(const glm::vec3& a, const glm::vec3& b) {
  return std::acos(std::clamp(glm::dot(glm::dvec3(a), glm::dvec3(b)), -1.0, 1.0));
}

// Uniform on the sphere: z uniform in [−1, 1] (Archimedes), φ uniform.
glm::dvec3 uniform_direction(Pcg32& rng) {
  const double z = 2.0 * rng.next_float() - 1.0;
  const double phi = 2.0 * kPi * rng.next_float();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

TEST(DirectionalBins, Nside1IsTheTwelveBasePixels) {
  const DirectionalBins bins(1);
  EXPECT_EQ(bins.bin_count(), 12);
  EXPECT_EQ(bins.ring_count(), 3);
  // HEALPix base pixels: 0–3 centered at z = 2/3, φ = π/4 + kπ/2; 4–7 on the equator at
  // φ = kπ/2; 8–11 at z = −2/3, φ = π/4 + kπ/2.
  for (int k = 0; k < 4; ++k) {
    const double phi_cap = kPi / 4 + k * kPi / 2;
    const double r_cap = std::sqrt(1.0 - 4.0 / 9.0);
    const glm::dvec3 north(r_cap * std::cos(phi_cap), r_cap * std::sin(phi_cap), 2.0 / 3.0);
    const glm::dvec3 equator(std::cos(k * kPi / 2), std::sin(k * kPi / 2), 0.0);
    const glm::dvec3 south(north.x, north.y, -2.0 / 3.0);
    EXPECT_LT(glm::length(glm::dvec3(bins.direction(k)) - north), 1e-6) << k;
    EXPECT_LT(glm::length(glm::dvec3(bins.direction(4 + k)) - equator), 1e-6) << k;
    EXPECT_LT(glm::length(glm::dvec3(bins.direction(8 + k)) - south), 1e-6) << k;
  }
  EXPECT_EQ(bins.bin_of(glm::vec3(0, 0, 1)), 0);
  EXPECT_EQ(bins.bin_of(glm::vec3(0, 0, -1)), 8);  // south pole: first pixel of the last ring
  EXPECT_EQ(bins.bin_of(glm::vec3(1, 0, 0)), 4);
  EXPECT_EQ(bins.bin_of(glm::vec3(0, 1, 0)), 5);
}

TEST(DirectionalBins, PolesAndRingLayoutForSeveralNside) {
  for (int nside : {2, 3, 4, 7, 16}) {
    const DirectionalBins bins(nside);
    ASSERT_EQ(bins.bin_count(), 12 * nside * nside);
    EXPECT_EQ(bins.bin_of(glm::vec3(0, 0, 1)), 0);
    EXPECT_EQ(bins.bin_of(glm::vec3(0, 0, -1)), bins.bin_count() - 4);
    // Rings 1..Nside−1 hold 4i bins, the 2Nside+1 rings of the belt 4Nside, the south cap
    // mirrors the north; rings are contiguous and their centers share z.
    int next_first = 0;
    for (int ring = 1; ring <= bins.ring_count(); ++ring) {
      const int from_pole = std::min(ring, 4 * nside - ring);
      EXPECT_EQ(bins.ring_bin_count(ring), 4 * std::min(from_pole, nside)) << ring;
      EXPECT_EQ(bins.ring_first_bin(ring), next_first) << ring;
      for (int b = next_first; b < next_first + bins.ring_bin_count(ring); ++b) {
        EXPECT_NEAR(bins.direction(b).z, bins.ring_z(ring), 1e-6);
      }
      next_first += bins.ring_bin_count(ring);
    }
    EXPECT_EQ(next_first, bins.bin_count());
    EXPECT_DOUBLE_EQ(bins.solid_angle() * bins.bin_count(), 4.0 * kPi);
  }
}

TEST(DirectionalBins, EveryCenterLooksUpItsOwnBin) {
  for (int nside : {1, 2, 3, 4, 5, 8, 9, 13, 16, 32}) {
    const DirectionalBins bins(nside);
    for (int j = 0; j < bins.bin_count(); ++j) {
      ASSERT_NEAR(glm::length(bins.direction(j)), 1.0f, 1e-6f);
      ASSERT_EQ(bins.bin_of(bins.direction(j)), j) << "nside " << nside;
      // Scale does not matter.
      ASSERT_EQ(bins.bin_of(3.5f * bins.direction(j)), j) << "nside " << nside;
    }
  }
}

TEST(DirectionalBins, DegenerateInputMapsToBinZero) {
  const DirectionalBins bins(4);
  EXPECT_EQ(bins.bin_of(glm::vec3(0.0f)), 0);
  EXPECT_EQ(bins.bin_of(glm::vec3(std::nanf(""), 0.0f, 1.0f)), 0);
  EXPECT_EQ(bins.bin_of(glm::vec3(INFINITY, 0.0f, 0.0f)), 0);
}

TEST(DirectionalBins, FromBinCountPicksTheClosestNside) {
  EXPECT_EQ(DirectionalBins::from_bin_count(48).bin_count(), 48);
  EXPECT_EQ(DirectionalBins::from_bin_count(128).bin_count(), 108);  // |108−128| < |192−128|
  EXPECT_EQ(DirectionalBins::from_bin_count(192).bin_count(), 192);
  EXPECT_EQ(DirectionalBins::from_bin_count(512).bin_count(), 588);   // |588−512| < |432−512|
  EXPECT_EQ(DirectionalBins::from_bin_count(1024).bin_count(), 972);  // vs 1200
  EXPECT_EQ(DirectionalBins::from_bin_count(3072).bin_count(), 3072);
  EXPECT_EQ(DirectionalBins::from_bin_count(0).nside(), 1);
  EXPECT_EQ(DirectionalBins::from_bin_count(int64_t{1} << 40).nside(), DirectionalBins::max_nside);
  EXPECT_EQ(DirectionalBins(0).nside(), 1);
}

// Uniform directions must fall into each bin with probability exactly 1/m. With N samples a
// bin's count is Binomial(N, 1/m); we allow 5 standard deviations per bin (a false alarm
// chance of ~6e-7 per bin, ~1e-4 over all bins of both cases; the seed is fixed anyway) and
// test the sum of squared standardized deviations, χ² with m − 1 degrees of freedom, against
// its mean plus 5 of its standard deviations sqrt(2(m − 1)). A bin of 5% too much or too little
// area would be ~2.2 (m = 48) and ~3.5 (m = 192) deviations off on its own.
TEST(DirectionalBins, UniformDirectionsFillBinsEqually) {
  for (int nside : {2, 4}) {
    const DirectionalBins bins(nside);
    const int m = bins.bin_count();
    const int64_t samples = int64_t{m} * (nside == 2 ? 20000 : 5000);
    std::vector<int64_t> counts(static_cast<size_t>(m), 0);
    Pcg32 rng(12345u + nside, 7u);
    for (int64_t s = 0; s < samples; ++s)
      ++counts[static_cast<size_t>(bins.bin_of(uniform_direction(rng)))];
    const double p = 1.0 / m;
    const double expected = samples * p;
    const double sd = std::sqrt(samples * p * (1.0 - p));
    double chi_square = 0.0;
    for (int j = 0; j < m; ++j) {
      const double z = (counts[static_cast<size_t>(j)] - expected) / sd;
      EXPECT_LT(std::abs(z), 5.0) << "nside " << nside << " bin " << j;
      chi_square += (counts[static_cast<size_t>(j)] - expected) *
                    (counts[static_cast<size_t>(j)] - expected) / expected;
    }
    EXPECT_LT(chi_square, (m - 1) + 5.0 * std::sqrt(2.0 * (m - 1))) << "nside " << nside;
  }
}

// The bin found for a direction is where the direction is: its center, or one of the bin's
// neighbors, is the nearest center (HEALPix pixels are not Voronoi cells, so the nearest center
// can be across an edge, but never further).
TEST(DirectionalBins, LookupAgreesWithNearestCenters) {
  const DirectionalBins bins(4);
  Pcg32 rng(99u, 3u);
  for (int s = 0; s < 20000; ++s) {
    const glm::dvec3 d = uniform_direction(rng);
    const int found = bins.bin_of(d);
    int nearest = 0;
    double best = -2.0;
    for (int j = 0; j < bins.bin_count(); ++j) {
      const double c = glm::dot(glm::dvec3(bins.direction(j)), d);
      if (c > best) {
        best = c;
        nearest = j;
      }
    }
    if (nearest == found) continue;
    const auto neighbors = bins.neighbors(found);
    EXPECT_NE(std::find(neighbors.begin(), neighbors.end(), nearest), neighbors.end())
        << "direction in bin " << found << " nearest to " << nearest;
  }
}

TEST(DirectionalBins, NeighborsAreSymmetricSortedAndTouching) {
  for (int nside : {2, 3, 4, 8, 16}) {
    const DirectionalBins bins(nside);
    const double spacing = bins.typical_spacing();
    EXPECT_DOUBLE_EQ(spacing, std::sqrt(4.0 * kPi / bins.bin_count()));
    const int equator = 2 * nside;
    for (int j = bins.ring_first_bin(equator);
         j < bins.ring_first_bin(equator) + bins.ring_bin_count(equator); ++j) {
      EXPECT_EQ(bins.neighbors(j).size(), 8u) << "equatorial bin " << j;
    }
    for (int j = 0; j < bins.bin_count(); ++j) {
      const auto neighbors = bins.neighbors(j);
      // 8 touching pixels in the belt, 6 or 7 of them in the caps (see the header).
      ASSERT_GE(neighbors.size(), 6u) << nside << " " << j;
      ASSERT_LE(neighbors.size(), 8u) << nside << " " << j;
      // The nearest neighbor sits about one spacing away (equal-area bins of side ~spacing).
      const double nearest = angle_between(bins.direction(j), bins.direction(neighbors[0]));
      EXPECT_GT(nearest, 0.6 * spacing);
      EXPECT_LT(nearest, 1.2 * spacing);
      double previous = 0.0;
      for (uint16_t l : neighbors) {
        ASSERT_NE(l, j);
        const double a = angle_between(bins.direction(j), bins.direction(l));
        EXPECT_GE(a, previous - 1e-12);
        EXPECT_LE(a, DirectionalBins::neighbor_radius_factor * spacing);
        previous = a;
        const auto back = bins.neighbors(l);
        EXPECT_NE(std::find(back.begin(), back.end(), static_cast<uint16_t>(j)), back.end());
      }
    }
  }
}

// The second moment E[θ²] of directions uniform over a spherical cap of half-angle α:
// ∫₀^α θ² sin θ dθ / (1 − cos α).
double cap_second_moment(double alpha) {
  const double integral = -alpha * alpha * std::cos(alpha) + 2.0 * alpha * std::sin(alpha) +
                          2.0 * std::cos(alpha) - 2.0;
  return integral / (1.0 - std::cos(alpha));
}

TEST(BinSpreading, ClassesStartAtOneBinAndReachTheMaximumCone) {
  for (int nside : {2, 4, 8}) {
    const DirectionalBins bins(nside);
    const BinSpreading spreading(bins);
    ASSERT_GE(spreading.class_count(), 2);
    EXPECT_DOUBLE_EQ(spreading.class_half_angle(0), bins.bin_cone_half_angle());
    EXPECT_DOUBLE_EQ(spreading.class_half_angle(spreading.class_count() - 1), kPi / 4);
    for (int k = 1; k < spreading.class_count(); ++k) {
      EXPECT_GT(spreading.class_half_angle(k), spreading.class_half_angle(k - 1));
      EXPECT_LE(spreading.class_half_angle(k),
                std::sqrt(2.0) * spreading.class_half_angle(k - 1) + 1e-12);
      // A cone of exactly the class's size maps to the class.
      const double cone = 2.0 * kPi * (1.0 - std::cos(spreading.class_half_angle(k)));
      EXPECT_EQ(spreading.class_of(cone), k);
    }
    const double bin = bins.solid_angle();
    EXPECT_EQ(spreading.class_of(0.0), 0);
    EXPECT_EQ(spreading.class_of(bin), 0);  // "if this is larger than that of a bin, we spread"
    EXPECT_EQ(spreading.class_of(1.01 * bin), 1);
    EXPECT_EQ(spreading.class_of(std::nan("")), 0);
    EXPECT_EQ(spreading.class_of(4.0 * kPi), spreading.class_count() - 1);
  }
}

TEST(BinSpreading, ConesOfOneBinAreTheIdentity) {
  const DirectionalBins bins(4);
  const BinSpreading spreading(bins);
  for (int j = 0; j < bins.bin_count(); ++j) {
    const SpreadFilter filter = spreading.filter(0, j);
    ASSERT_EQ(filter.bins.size(), 1u);
    ASSERT_EQ(filter.weights.size(), 1u);
    EXPECT_EQ(filter.bins[0], j);
    EXPECT_EQ(filter.weights[0], 1.0f);
  }
}

// Every filter moves exactly the flux it is given (weights sum to 1 up to float rounding of a
// few hundred terms, 1e-5), starts at its own bin, holds each bin once, and its weights fall
// with the angle from the center (the filtered cap is radially non-increasing).
TEST(BinSpreading, FiltersPreserveEnergyAndFallWithAngle) {
  for (int nside : {2, 4, 8}) {
    const DirectionalBins bins(nside);
    const BinSpreading spreading(bins);
    for (int k = 0; k < spreading.class_count(); ++k) {
      for (int j = 0; j < bins.bin_count(); ++j) {
        const SpreadFilter filter = spreading.filter(k, j);
        ASSERT_EQ(filter.bins.size(), filter.weights.size());
        ASSERT_EQ(filter.bins[0], j);
        double sum = 0.0;
        double previous_angle = 0.0;
        float previous_weight = 1.0f;
        std::set<uint16_t> seen;
        for (size_t e = 0; e < filter.bins.size(); ++e) {
          ASSERT_TRUE(seen.insert(filter.bins[e]).second);
          ASSERT_GT(filter.weights[e], 0.0f);
          const double angle = angle_between(bins.direction(j), bins.direction(filter.bins[e]));
          ASSERT_GE(angle, previous_angle - 1e-9);
          ASSERT_LE(filter.weights[e], previous_weight * (1.0f + 1e-5f));
          previous_angle = angle;
          previous_weight = filter.weights[e];
          sum += filter.weights[e];
        }
        ASSERT_NEAR(sum, 1.0, 1e-5) << "nside " << nside << " class " << k << " bin " << j;
      }
    }
  }
}

// The spread is centered, the same around every bin, and as wide as the cone blurred by the
// Gaussian: E[θ²] = E_cap[θ²] + (what the Gaussian adds). A 2D Gaussian of standard deviation
// σ has E[r²] = 2σ²; cut at 2.5σ (the support) that falls to 2σ²(1 − 3.125 e^−3.125/(1 −
// e^−3.125)) ≈ 1.63σ² for a point-like cone, and for a wide cone the cut is 2.5σ beyond its edge,
// so most of the 2σ² remains. The sphere's curvature and the finite set of bin centers (worst at
// m = 48, σ ≈ 29°) move it by a few tenths of σ²: we accept [1.4σ², 2.3σ²].
TEST(BinSpreading, SpreadIsCenteredRotationInvariantAndGrowsWithTheCone) {
  for (int nside : {2, 4, 8}) {
    const DirectionalBins bins(nside);
    const BinSpreading spreading(bins);
    const double sigma_sq = bins.solid_angle();
    double previous_moment = 0.0;
    for (int k = 1; k < spreading.class_count(); ++k) {
      double moment_sum = 0.0;
      float center_min = 1.0f;
      float center_max = 0.0f;
      for (int j = 0; j < bins.bin_count(); ++j) {
        const SpreadFilter filter = spreading.filter(k, j);
        glm::dvec3 mean(0.0);
        double moment = 0.0;
        for (size_t e = 0; e < filter.bins.size(); ++e) {
          const glm::vec3& d = bins.direction(filter.bins[e]);
          const double angle = angle_between(bins.direction(j), d);
          mean += static_cast<double>(filter.weights[e]) * glm::dvec3(d);
          moment += filter.weights[e] * angle * angle;
        }
        // No bias: the weighted mean direction stays within a quarter spacing of ω_j.
        EXPECT_LT(angle_between(glm::vec3(glm::normalize(mean)), bins.direction(j)),
                  0.25 * bins.typical_spacing());
        moment_sum += moment;
        center_min = std::min(center_min, filter.weights[0]);
        center_max = std::max(center_max, filter.weights[0]);
      }
      const double moment = moment_sum / bins.bin_count();
      const double added = (moment - cap_second_moment(spreading.class_half_angle(k))) / sigma_sq;
      EXPECT_GT(added, 1.4) << "nside " << nside << " class " << k;
      EXPECT_LT(added, 2.3) << "nside " << nside << " class " << k;
      EXPECT_GT(moment, previous_moment) << "nside " << nside << " class " << k;
      previous_moment = moment;
      // One radial profile for all bins; only its normalization follows the local arrangement
      // of bin centers, which equal areas keep within a few percent.
      EXPECT_LT(center_max / center_min, 1.08f) << "nside " << nside << " class " << k;
    }
  }
}

// Sparse: the tables hold the entries within each cone plus its blur, far below the dense
// m × m table per cone size of §4.2.
TEST(BinSpreading, TablesAreSparse) {
  const DirectionalBins bins(8);
  const BinSpreading spreading(bins);
  const size_t m = static_cast<size_t>(bins.bin_count());
  const size_t dense = (spreading.class_count() - 1) * m * m * sizeof(float);
  EXPECT_GT(spreading.memory_bytes(), m * sizeof(uint16_t));
  EXPECT_LT(spreading.memory_bytes(), dense / 2);
  size_t entries = 0;
  for (int k = 1; k < spreading.class_count(); ++k) {
    for (int j = 0; j < bins.bin_count(); ++j) entries += spreading.filter(k, j).bins.size();
  }
  EXPECT_LE(entries * (sizeof(uint16_t) + sizeof(float)), spreading.memory_bytes());
}

TEST(BinSpreading, NoSpreadClassesWhenTheMaximumConeIsOneBin) {
  const DirectionalBins bins(4);
  const BinSpreading spreading(bins, 0.5 * bins.bin_cone_half_angle());
  EXPECT_EQ(spreading.class_count(), 1);
  EXPECT_EQ(spreading.class_of(4.0 * kPi), 0);
  EXPECT_EQ(spreading.filter(0, 17).bins[0], 17);
}

}  // namespace
}  // namespace bakegi::antiradiance
