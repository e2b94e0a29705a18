// mission/route_timetable: a collector's route as a function of time, checked
// by hand on the corridor (tests/core/corridor.hpp).
#include "gather_core/mission/route_timetable.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "corridor.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace mission {
namespace {

// The corridor's OC coverage by hand: cell centres within 2 m of the OC at
// x = 0.55 m, i.e. columns 0..25 (x < 2.6 m).
Mask corridor_coverage(const OccupancyGrid& g) {
  Mask cov(g.frame(), 0);
  for (int r = 0; r < g.height(); ++r)
    for (int c = 0; c <= 25; ++c) cov.at(Cell{r, c}) = 1;
  return cov;
}

// OC (x = 0.55) -> x = 15.05 -> OC: 29 m at 1 m/s, requests every 100 s.
plan::CollectorRoute out_and_back() {
  plan::CollectorRoute r;
  r.waypoints = {{0.55, 0.25}, {15.05, 0.25}, {0.55, 0.25}};
  return r;
}

TEST(RouteTimetableTest, PositionAlongTheLoopsOfARequestPeriod) {
  const Scenario s = testing_support::corridor();
  const RouteTimetable rt(out_and_back(), 1.0, 100.0, corridor_coverage(s.grid));
  EXPECT_FALSE(rt.idle());
  EXPECT_NEAR(rt.length(), 29.0, 1e-12);
  EXPECT_NEAR(rt.period(), 29.0, 1e-12);
  EXPECT_EQ(rt.schedule().loops(), 3);  // 3 loops of 29 s fit a 100 s period
  EXPECT_NEAR(rt.position(0.0).x, 0.55, 1e-9);
  EXPECT_NEAR(rt.position(10.0).x, 10.55, 1e-9);
  EXPECT_NEAR(rt.position(14.5).x, 15.05, 1e-9);
  EXPECT_NEAR(rt.position(20.0).x, 9.55, 1e-9);    // on the way back
  EXPECT_NEAR(rt.position(39.0).x, 10.55, 1e-9);   // second loop
  EXPECT_NEAR(rt.position(90.0).x, 0.55, 1e-9);    // waiting at the OC after 3 loops (87 s)
  EXPECT_NEAR(rt.position(110.0).x, 10.55, 1e-9);  // the next request's first loop
  EXPECT_NEAR(rt.position(20.0).y, 0.25, 1e-12);
}

TEST(RouteTimetableTest, NextPassAtAnArcPosition) {
  const Scenario s = testing_support::corridor();
  const RouteTimetable rt(out_and_back(), 1.0, 100.0, corridor_coverage(s.grid));
  EXPECT_NEAR(rt.next_time_at(14.5, 0.0), 14.5, 1e-9);
  EXPECT_NEAR(rt.next_time_at(14.5, 14.5), 14.5, 1e-9);
  EXPECT_NEAR(rt.next_time_at(14.5, 14.5 + 5e-4), 14.5, 1e-9);  // within the 1 ms tolerance
  EXPECT_NEAR(rt.next_time_at(14.5, 15.0), 43.5, 1e-9);
  EXPECT_NEAR(rt.next_time_at(14.5, 75.0), 114.5, 1e-9);  // no 4th loop: the next request's
  EXPECT_NEAR(rt.next_time_at(20.0, 0.0), 20.0, 1e-9);    // arc 20 m: x = 9.55 on the way back
}

TEST(RouteTimetableTest, CoverageIntervalsAndTheNextTimeInCoverage) {
  const Scenario s = testing_support::corridor();
  const RouteTimetable rt(out_and_back(), 1.0, 100.0, corridor_coverage(s.grid));
  // Inside while x < 2.6: arcs [0, 2.05] and [26.95, 29].
  const auto& in = rt.coverage_intervals();
  ASSERT_EQ(in.size(), 2u);
  EXPECT_NEAR(in[0].first, 0.0, 1e-12);
  EXPECT_NEAR(in[0].second, 2.05, 1e-5);
  EXPECT_NEAR(in[1].first, 26.95, 1e-5);
  EXPECT_NEAR(in[1].second, 29.0, 1e-12);
  EXPECT_NEAR(rt.next_coverage_time(1.0), 1.0, 1e-12);
  EXPECT_NEAR(rt.next_coverage_time(5.0), 26.95, 1e-5);
  EXPECT_NEAR(rt.next_coverage_time(34.0), 55.95, 1e-5);  // second loop, arc 5
  EXPECT_NEAR(rt.next_coverage_time(90.0), 90.0, 1e-12);  // waiting at the OC
}

TEST(RouteTimetableTest, AnIdleRouteNeverMovesAndIsNeverMet) {
  const Scenario s = testing_support::corridor();
  plan::CollectorRoute idle;
  idle.waypoints = {{0.55, 0.25}};
  const RouteTimetable rt(idle, 1.0, 100.0, corridor_coverage(s.grid));
  EXPECT_TRUE(rt.idle());
  EXPECT_EQ(rt.period(), 0.0);
  EXPECT_NEAR(rt.position(50.0).x, 0.55, 1e-12);
  EXPECT_EQ(rt.next_time_at(0.0, 3.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(rt.next_coverage_time(3.0), 3.0);
}

TEST(RouteTimetableTest, BadRoutesAreClearErrors) {
  const Scenario s = testing_support::corridor();
  const Mask cov = corridor_coverage(s.grid);
  EXPECT_THROW(RouteTimetable(out_and_back(), 0.0, 100.0, cov), Error);
  EXPECT_THROW(RouteTimetable(out_and_back(), 1.0, 0.0, cov), Error);
  plan::CollectorRoute far;
  far.waypoints = {{10.05, 0.25}, {15.05, 0.25}, {10.05, 0.25}};
  try {
    RouteTimetable(far, 1.0, 100.0, cov);
    FAIL() << "a route outside the coverage was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("never enters the OC's coverage"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mission
}  // namespace gather
