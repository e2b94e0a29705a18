// plan/loop_schedule: when a collector drives its loops, by hand.
#include "gather_core/plan/loop_schedule.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace gather
