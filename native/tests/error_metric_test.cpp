// The project's error metric (native/common/error_metric.h) on cases whose value is known exactly.
#include "error_metric.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace bakegi {
namespace {

TEST(ErrorMetric, IdenticalValuesHaveZeroError) {
  const std::vector<float> r = {0.1f, 0.2f, 0.3f, 1.0f, 2.0f, 3.0f};
  EXPECT_EQ(*relative_rmse_luminance(r.data(), r.data(), 2), 0.0);
}

TEST(ErrorMetric, UniformScaleErrorIsTheScale) {
  // v = (1 + a) r gives e = |a| whatever r is: the metric is relative.
  const std::vector<float> r = {0.5f, 0.25f, 4.0f, 1.0f, 3.0f, 0.125f};
  std::vector<float> v;
  for (const float x : r) v.push_back(1.1f * x);
  EXPECT_NEAR(*relative_rmse_luminance(v.data(), r.data(), 2), 0.1, 1e-6);
}

TEST(ErrorMetric, ChannelsAreWeightedByRec709Luminance) {
  // Reference grey 1, value off by d in one channel only: e = sqrt(w_c d^2 / sum w) and
  // the Rec. 709 weights sum to 1.
  const std::vector<float> r = {1.0f, 1.0f, 1.0f};
  const float d = 0.5f;
  for (int c = 0; c < 3; ++c) {
    std::vector<float> v = r;
    v[c] += d;
    EXPECT_NEAR(*relative_rmse_luminance(v.data(), r.data(), 1),
                std::sqrt(kLuminanceWeights[c] * d * d), 1e-6)
        << "channel " << c;
  }
}

TEST(ErrorMetric, IsUndefinedWithoutPointsOrSignalOrForNonFiniteValues) {
  const std::vector<float> zero = {0.0f, 0.0f, 0.0f};
  const std::vector<float> one = {1.0f, 1.0f, 1.0f};
  std::vector<float> nan = one;
  nan[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(relative_rmse_luminance(one.data(), one.data(), 0));
  EXPECT_FALSE(relative_rmse_luminance(one.data(), zero.data(), 1));
  EXPECT_FALSE(relative_rmse_luminance(nan.data(), one.data(), 1));
  EXPECT_FALSE(relative_rmse_luminance(one.data(), nan.data(), 1));
}

TEST(ErrorMetric, ProjectMetricsOnGreyPoints) {
  // Grey points (luminance = the value): reference 1 and 3, values 1.5 and 2.
  // NRMSE = sqrt(((0.5)^2 + (1)^2) / 2) / 2; wRRMSE = sqrt((0.25 / 1 + 1 / 3) / 4).
  const std::vector<float> r = {1.0f, 1.0f, 1.0f, 3.0f, 3.0f, 3.0f};
  const std::vector<float> v = {1.5f, 1.5f, 1.5f, 2.0f, 2.0f, 2.0f};
  const auto m = error_metrics(v.data(), r.data(), 2);
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->nrmse, std::sqrt((0.25 + 1.0) / 2.0) / 2.0, 1e-6);
  EXPECT_NEAR(m->weighted_relative_rmse, std::sqrt((0.25 + 1.0 / 3.0) / 4.0), 1e-6);
  EXPECT_NEAR(m->relative_rmse, *relative_rmse_luminance(v.data(), r.data(), 2), 1e-12);
}

TEST(ErrorMetric, WeightedRelativeRmseLeavesOutUnlitPoints) {
  // A point whose reference is under 1% of the mean counts in the NRMSE, not in the
  // weighted relative RMSE (which divides by the reference).
  const std::vector<float> r = {2.0f, 2.0f, 2.0f, 0.001f, 0.001f, 0.001f};
  const std::vector<float> v = {2.0f, 2.0f, 2.0f, 0.5f, 0.5f, 0.5f};
  const auto m = error_metrics(v.data(), r.data(), 2);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->weighted_relative_rmse, 0.0);
  EXPECT_GT(m->nrmse, 0.3);
}

}  // namespace
}  // namespace bakegi
