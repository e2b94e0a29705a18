// plan/loop_schedule: when a collector drives its loops, by hand.
#include "gather_core/plan/loop_schedule.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

namespace gather {
namespace {

TEST(LoopScheduleTest, LoopsFitIntoTheRequestPeriod) {
  const plan::LoopSchedule s(29.0, 100.0);  // 3 loops per request, then 13 s at the OC
  EXPECT_EQ(s.loops(), 3);
  EXPECT_DOUBLE_EQ(s.super_period(), 100.0);
  EXPECT_DOUBLE_EQ(s.next_departure(0.0), 0.0);
  EXPECT_DOUBLE_EQ(s.next_departure(30.0), 58.0);
  EXPECT_DOUBLE_EQ(s.next_departure(90.0), 100.0);
  EXPECT_DOUBLE_EQ(s.next_at(14.5, 18.5), 43.5);
  EXPECT_DOUBLE_EQ(s.next_at(14.5, 80.0), 114.5);
  EXPECT_DOUBLE_EQ(s.offset_at(35.0), 6.0);
  EXPECT_DOUBLE_EQ(s.offset_at(90.0), 29.0);  // waiting at the OC
}

TEST(LoopScheduleTest, LongRouteIsDrivenBackToBack) {
  const plan::LoopSchedule s(29.0, 10.0);  // longer than T: no waiting
  EXPECT_EQ(s.loops(), 1);
  EXPECT_DOUBLE_EQ(s.super_period(), 29.0);
  EXPECT_DOUBLE_EQ(s.next_departure(10.0), 29.0);
  EXPECT_DOUBLE_EQ(s.next_at(14.5, 15.0), 43.5);
  EXPECT_DOUBLE_EQ(s.offset_at(25.0), 25.0);
  EXPECT_DOUBLE_EQ(s.offset_at(29.5), 0.5);
  const plan::LoopSchedule exact(20.0, 20.0);  // a route of exactly T: back to back
  EXPECT_EQ(exact.loops(), 1);
  EXPECT_DOUBLE_EQ(exact.next_departure(5.0), 20.0);
}

TEST(LoopScheduleTest, AnIdleCollectorNeverLeavesTheOc) {
  const plan::LoopSchedule idle(0.0, 10.0);
  EXPECT_TRUE(idle.idle());
  EXPECT_TRUE(std::isinf(idle.next_at(1.0, 0.0)));
  EXPECT_DOUBLE_EQ(idle.next_departure(3.5), 3.5);
  EXPECT_DOUBLE_EQ(idle.offset_at(7.0), 0.0);
  EXPECT_TRUE(plan::LoopSchedule(-4.0, 10.0).idle());  // a negative travel time is an idle route too
}

TEST(LoopScheduleTest, HalfThePeriodFitsTwiceDespiteRounding) {
  const plan::LoopSchedule half(0.1 * 3.0 / 2.0, 0.3);  // 0.15 s twice in 0.3 s, neither exactly representable
  EXPECT_EQ(half.loops(), 2);
  EXPECT_DOUBLE_EQ(half.super_period(), 0.3);
  EXPECT_NEAR(half.next_departure(0.01), 0.15, 1e-12);
  EXPECT_NEAR(half.next_departure(0.16), 0.3, 1e-12);
}

TEST(LoopScheduleTest, LastDepartureIsTheLatestLoopStartAtOrBeforeT) {
  const plan::LoopSchedule s(29.0, 100.0);        // loops at 0, 29, 58; then 100, 129, 158; ...
  EXPECT_DOUBLE_EQ(s.last_departure(-5.0), 0.0);  // before the first
  EXPECT_DOUBLE_EQ(s.last_departure(0.0), 0.0);
  EXPECT_DOUBLE_EQ(s.last_departure(28.9), 0.0);
  EXPECT_DOUBLE_EQ(s.last_departure(29.0), 29.0);  // at a departure: that one
  EXPECT_DOUBLE_EQ(s.last_departure(57.9), 29.0);
  EXPECT_DOUBLE_EQ(s.last_departure(58.0), 58.0);
  EXPECT_DOUBLE_EQ(s.last_departure(90.0), 58.0);  // waiting at the OC: the third loop is the latest
  EXPECT_DOUBLE_EQ(s.last_departure(99.99), 58.0);
  EXPECT_DOUBLE_EQ(s.last_departure(100.0), 100.0);
  EXPECT_DOUBLE_EQ(s.last_departure(150.0), 129.0);
  EXPECT_DOUBLE_EQ(s.last_departure(250.0), 229.0);

  const plan::LoopSchedule back_to_back(29.0, 10.0);  // no waiting: every 29 s
  EXPECT_DOUBLE_EQ(back_to_back.last_departure(10.0), 0.0);
  EXPECT_DOUBLE_EQ(back_to_back.last_departure(30.0), 29.0);
  EXPECT_DOUBLE_EQ(back_to_back.last_departure(57.9), 29.0);
  EXPECT_DOUBLE_EQ(back_to_back.last_departure(58.0), 58.0);

  const plan::LoopSchedule idle(0.0, 10.0);  // never leaves
  EXPECT_DOUBLE_EQ(idle.last_departure(55.0), 0.0);

  const plan::LoopSchedule half(0.1 * 3.0 / 2.0, 0.3);  // 0.15 s twice in 0.3 s, neither exactly representable
  EXPECT_NEAR(half.last_departure(0.16), 0.15, 1e-12);
  EXPECT_NEAR(half.last_departure(0.29), 0.15, 1e-12);
  EXPECT_NEAR(half.last_departure(0.31), 0.3, 1e-12);
}

// Between two departures: last_departure(t) <= t, no departure in
// (last_departure(t), t], and it is itself a departure.
TEST(LoopScheduleTest, NoDepartureLiesBetweenTheLastDepartureAndT) {
  for (const auto& [travel, period] :
       std::vector<std::pair<double, double>>{{29.0, 100.0}, {29.0, 10.0}, {0.15, 0.3}, {89.2, 233.2}, {20.0, 20.0}}) {
    const plan::LoopSchedule s(travel, period);
    for (int k = 1; k < 2000; ++k) {
      const double t = k * 0.0173 * period;
      const double last = s.last_departure(t);
      ASSERT_LE(last, t) << travel << " " << period << " t " << t;
      ASSERT_GT(s.next_departure(last + 1e-9 * period), t - 1e-9 * period) << travel << " " << period << " t " << t;
      ASSERT_NEAR(s.next_departure(last), last, 1e-9 * period) << travel << " " << period << " t " << t;
    }
  }
}

// At the very time next_departure() names, that departure is the latest.
TEST(LoopScheduleTest, AtADepartureTheLastDepartureIsThatOne) {
  const plan::LoopSchedule s(89.2, 233.2);        // two loops a period: at 0 and 89.2 s after each request
  const double depart = s.next_departure(600.0);  // the request at 3 x 233.2 s
  EXPECT_NEAR(depart, 699.6, 1e-9);
  // next_departure(600) is 3 * 233.2 = 699.5999999999999 in doubles; without
  // next_departure()'s tolerance, floor(2.9999999999999996) = 2 gave the
  // second loop of the period before, 555.6 s: 144 s too early.
  EXPECT_NEAR(s.last_departure(depart), depart, 1e-9);
  const plan::LoopSchedule half(0.15, 0.3);
  const double at = half.next_departure(2.0);  // 7 x 0.3 = 2.0999999999999996
  EXPECT_NEAR(at, 2.1, 1e-9);
  EXPECT_NEAR(half.last_departure(at), at, 1e-9);  // (was 1.95)
}

}  // namespace
}  // namespace gather
