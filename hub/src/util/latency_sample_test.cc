#include "util/latency_sample.h"

#include <gtest/gtest.h>

namespace mocap {
namespace {

TEST(LatencySample, ExactWhileTheReservoirHoldsEverything) {
  LatencySample sample(1000);
  EXPECT_EQ(sample.Percentile(50), 0.0);
  for (int i = 100; i >= 1; --i) sample.Add(i);
  EXPECT_EQ(sample.count(), 100u);
  EXPECT_EQ(sample.max(), 100.0);
  EXPECT_EQ(sample.Percentile(0), 1.0);
  EXPECT_EQ(sample.Percentile(50), 51.0);
  EXPECT_EQ(sample.Percentile(99), 100.0);
  EXPECT_EQ(sample.Percentile(100), 100.0);
}

TEST(LatencySample, BoundedMemoryKeepsTheDistributionAndTheTrueMaximum) {
  LatencySample sample(500);
  // 100 000 values uniform over [0, 1000) in a scrambled order, one outlier in the middle.
  for (uint64_t i = 0; i < 100000; ++i) sample.Add(static_cast<double>((i * 7919) % 100000) / 100.0);
  sample.Add(5000.0);
  for (uint64_t i = 0; i < 1000; ++i) sample.Add(1.0);
  EXPECT_EQ(sample.count(), 101001u);
  EXPECT_EQ(sample.max(), 5000.0);
  EXPECT_NEAR(sample.Percentile(50), 500.0, 60.0);
  EXPECT_NEAR(sample.Percentile(90), 900.0, 40.0);
}

}  // namespace
}  // namespace mocap
