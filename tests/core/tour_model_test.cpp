// plan/tour_model and plan/estimate's small pieces, by hand: the tour length
// and its inverse, the share of a segment within reach, the goals measured
// within a budget, the binomial goal count, a tour model from a segment.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "gather_core/plan/estimate.hpp"
#include "gather_core/plan/tour_model.hpp"

namespace gather {
namespace plan {
namespace {

TourModel square(double out, double back, double side) {
  TourModel m;
  m.out = out, m.back = back, m.side = side, m.c = 0.7124;
  return m;
}

TEST(TourModelTest, LengthByHandAndItsInverse) {
  const TourModel m = square(10.0, 6.0, 20.0);
  EXPECT_DOUBLE_EQ(m.length(0.0), 0.0);
  EXPECT_DOUBLE_EQ(m.length(0.5), 8.0);  // half the trip out and back
  EXPECT_DOUBLE_EQ(m.length(1.0), 16.0);
  EXPECT_NEAR(m.length(4.0), 16.0 + 0.7124 * 20.0 * 3.0 / 2.0, 1e-12);
  for (const double n : {1.0, 2.0, 7.0, 30.0}) EXPECT_NEAR(m.goals_within(m.length(n), 100.0), n, 1e-9) << n;
  EXPECT_DOUBLE_EQ(m.goals_within(8.0, 100.0), 0.5);
  EXPECT_DOUBLE_EQ(m.goals_within(1e9, 12.0), 12.0);  // never more than wanted
  EXPECT_DOUBLE_EQ(m.partial_length(4.0, 4.0), m.length(4.0));
  EXPECT_NEAR(m.partial_length(2.0, 4.0), 16.0 + 0.7124 * 20.0 / 2.0, 1e-12);
}

TEST(TourModelTest, ShareWithinReachFromQuantilesAndGoalsMeasured) {
  TourModel m = square(10.0, 0.0, 20.0);
  EXPECT_DOUBLE_EQ(m.within(5.0), 0.5);  // no quantiles: d / out
  m.out_quantiles = {0.0, 10.0, 20.0};   // half the cells within 10 m, all within 20 m
  EXPECT_DOUBLE_EQ(m.within(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(m.within(5.0), 0.25);
  EXPECT_DOUBLE_EQ(m.within(10.0), 0.5);
  EXPECT_DOUBLE_EQ(m.within(25.0), 1.0);
  // One goal, 10 m of budget: measured when it lies within reach (F = 0.5).
  EXPECT_DOUBLE_EQ(m.measured(1.0, 10.0), 0.5);
  // Four goals: the first with 1 - 0.5^4, never more than 4 F = 2 within reach.
  EXPECT_DOUBLE_EQ(m.measured(4.0, 10.0), 1.0 - std::pow(0.5, 4));
  EXPECT_DOUBLE_EQ(m.measured(4.0, 19.0), std::min(4.0 * m.within(19.0), 1.0 - std::pow(1.0 - m.within(19.0), 4) +
                                                                             9.0 * 2.0 / (0.7124 * 20.0)));
  EXPECT_DOUBLE_EQ(m.measured(0.0, 10.0), 0.0);
  // Continuous in the budget.
  EXPECT_NEAR(m.measured(4.0, 10.0 - 1e-9), m.measured(4.0, 10.0 + 1e-9), 1e-6);
}

TEST(TourModelTest, FromASegment) {
  WorkerSegment seg;
  seg.area = 100.0;
  seg.mean_pair_distance = 2.0 * kSquarePairDistance * 10.0;  // twice an open square's walks
  seg.mean_home_distance = 12.0, seg.mean_coverage_distance = 7.0, seg.mean_oc_distance = 15.0;
  seg.home_quantiles = {1.0, 2.0}, seg.oc_quantiles = {3.0, 4.0};
  seg.touches_coverage = true;
  const TourModel oc = tour_model(seg, true, 0.7);
  EXPECT_DOUBLE_EQ(oc.side, 20.0);
  EXPECT_DOUBLE_EQ(oc.out, 12.0);
  EXPECT_DOUBLE_EQ(oc.back, 7.0);
  EXPECT_EQ(oc.out_quantiles, seg.home_quantiles);
  const TourModel first = first_trip(seg, oc);
  EXPECT_DOUBLE_EQ(first.out, 15.0);
  EXPECT_EQ(first.out_quantiles, seg.oc_quantiles);
  EXPECT_DOUBLE_EQ(first.back, 7.0);
  seg.mean_pair_distance = 0.0;  // not measured: an open square's side
  EXPECT_DOUBLE_EQ(tour_model(seg, false, 0.7).side, 10.0);
}

TEST(EstimateTest, GoalCountIsBinomialAndItsTailIsDropped) {
  const std::vector<double> pmf = goal_count_pmf(4, 0.25);
  ASSERT_EQ(pmf.size(), 5u);
  EXPECT_NEAR(pmf[0], std::pow(0.75, 4), 1e-12);
  EXPECT_NEAR(pmf[1], 4 * 0.25 * std::pow(0.75, 3), 1e-12);
  EXPECT_NEAR(pmf[4], std::pow(0.25, 4), 1e-12);
  EXPECT_NEAR(std::accumulate(pmf.begin(), pmf.end(), 0.0), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(goal_count_pmf(6, 0.0)[0], 1.0);
  EXPECT_DOUBLE_EQ(goal_count_pmf(6, 1.0)[6], 1.0);
  // 1000 goals, p = 0.55: no underflow, the mass where it should be.
  const std::vector<double> big = goal_count_pmf(1000, 0.55);
  double mean = 0.0;
  for (std::size_t n = 0; n < big.size(); ++n) mean += static_cast<double>(n) * big[n];
  EXPECT_NEAR(mean, 550.0, 1e-6);
  EXPECT_NEAR(std::accumulate(big.begin(), big.end(), 0.0), 1.0, 1e-9);
}

TEST(EstimateTest, MeanIntervalOverAWorkersAreas) {
  EXPECT_DOUBLE_EQ(mean_interval({}, 500.0), 500.0);
  AreaDeliveries a, b;
  for (int i = 0; i < 5; ++i) a.delivery(100.0 * i, 1.0);
  const double ia = a.interval(500.0), ib = b.interval(500.0);
  EXPECT_DOUBLE_EQ(mean_interval({a, b}, 500.0), 0.5 * (ia + ib));
}

}  // namespace
}  // namespace plan
}  // namespace gather
