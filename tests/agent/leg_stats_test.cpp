// motion/leg_stats: how late a robot reached its waypoints, by hand: the
// late threshold (more than 0.5 s), the median of the late legs to 0.1 s
// (the middle bin's centre, never above the maximum), the exact maximum,
// and nothing late.
#include "gather_agent/motion/leg_stats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace gather {
namespace agent {
namespace {

TEST(LegStats, NothingLateIsZeroesWithEveryLegCounted) {
  LegStats s;
  EXPECT_EQ(s.legs(), 0);
  EXPECT_EQ(s.late(), 0);
  EXPECT_EQ(s.median_late(), 0.0);
  EXPECT_EQ(s.max_late(), 0.0);
  // Early, on time, and late by at most the threshold: legs, none late.
  for (const double lateness : {-12.0, -0.3, 0.0, 0.25, 0.49, 0.5}) s.add(lateness);
  EXPECT_EQ(s.legs(), 6);
  EXPECT_EQ(s.late(), 0);
  EXPECT_EQ(s.median_late(), 0.0);
  EXPECT_EQ(s.max_late(), 0.0);
}

TEST(LegStats, LateMeansMoreThanHalfASecond) {
  EXPECT_EQ(LegStats::kLateAfter, 0.5);
  LegStats s;
  s.add(0.5);                                       // exactly the threshold: not late
  s.add(std::nextafter(0.5, 1.0));                  // just past it: late
  s.add(std::numeric_limits<double>::quiet_NaN());  // not a number: a leg, never late
  s.add(-std::numeric_limits<double>::infinity());  // absurdly early: a leg, not late
  EXPECT_EQ(s.legs(), 4);
  EXPECT_EQ(s.late(), 1);
  EXPECT_EQ(s.max_late(), std::nextafter(0.5, 1.0));
}

TEST(LegStats, OneLateLegIsItsOwnMedianAndMaximumExactly) {
  LegStats s;
  s.add(0.2);
  s.add(0.73);  // bin [0.7, 0.8): its centre 0.75 is above the only value; the median is capped at the maximum
  EXPECT_EQ(s.legs(), 2);
  EXPECT_EQ(s.late(), 1);
  EXPECT_EQ(s.max_late(), 0.73);
  EXPECT_EQ(s.median_late(), 0.73);
}

TEST(LegStats, TheMedianOfTheLateLegsIsTheMiddleBinsCentreAndTheMaximumIsExact) {
  LegStats s;
  // Late: 0.7, 1.23, 5.0 (median 1.23, in bin [1.2, 1.3): 1.25); on time: 0.1, 0.4 (not in the median).
  for (const double lateness : {5.0, 0.1, 1.23, 0.4, 0.7}) s.add(lateness);
  EXPECT_EQ(s.legs(), 5);
  EXPECT_EQ(s.late(), 3);
  EXPECT_DOUBLE_EQ(s.median_late(), 1.25);
  EXPECT_EQ(s.max_late(), 5.0);
  // Two more late legs above: the middle of {0.7, 1.23, 5.0, 7.31, 9.99} is
  // 5.0, in bin [5.0, 5.1): 5.05.
  s.add(7.31);
  s.add(9.99);
  EXPECT_EQ(s.late(), 5);
  EXPECT_DOUBLE_EQ(s.median_late(), 5.05);
  EXPECT_EQ(s.max_late(), 9.99);
}

TEST(LegStats, TheMedianOfManyLateLegsIsWithinHalfABinOfTheTrueMedian) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> late(0.51, 120.0);
  LegStats s;
  std::vector<double> values;
  for (int i = 0; i < 301; ++i) {  // odd: one middle value
    const double v = late(rng);
    values.push_back(v);
    s.add(v);
    s.add(0.1);  // on-time legs in between change nothing of the late ones
  }
  std::nth_element(values.begin(), values.begin() + 150, values.end());
  const double median = values[150];
  EXPECT_EQ(s.legs(), 602);
  EXPECT_EQ(s.late(), 301);
  EXPECT_NEAR(s.median_late(), median, 0.05 + 1e-9);
  EXPECT_EQ(s.max_late(), *std::max_element(values.begin(), values.end()));
  EXPECT_LE(s.median_late(), s.max_late());
}

TEST(LegStats, BeyondTheLastBinTheMaximumStaysExactAndTheMedianSaturates) {
  LegStats s;
  s.add(700.0);  // past the 600 s of bins
  s.add(900.0);
  s.add(1000.0);
  EXPECT_EQ(s.late(), 3);
  EXPECT_EQ(s.max_late(), 1000.0);
  // Counted in the last bin [599.9, 600): its centre.
  EXPECT_DOUBLE_EQ(s.median_late(), 599.95);
}

}  // namespace
}  // namespace agent
}  // namespace gather
