// motion/route_base: the ideal collector base is where its timetable says
// while it drives a loop on time, drives any other command straight at the
// planned pace, and reports every waypoint at its planned time.
#include "gather_agent/motion/route_base.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "corridor_team.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;

// The loop of `route` leaving at `depart`, from vertex `first` on.
std::vector<Waypoint> loop(const mission::RouteTimetable& route, double depart, std::size_t first = 1) {
  std::vector<Waypoint> legs;
  for (std::size_t v = first; v < route.waypoints().size(); ++v)
    legs.push_back(Waypoint{route.waypoints()[v], depart + route.arcs()[v] / route.speed()});
  return legs;
}

TEST(RouteBase, OnTimeLoopsAreItsTimetableBitForBit) {
  CorridorTeam c;
  const mission::RouteTimetable& route = c.team->routes[CollectorId(0)];
  RouteBase base(route, Point2{0.55, 0.25}, route.waypoints().size());
  base.update(3.0);
  EXPECT_DOUBLE_EQ(base.pose().x, 0.55);  // no command yet: where it started
  EXPECT_EQ(base.state(), NavState::kIdle);
  const std::vector<Waypoint> first = loop(route, 0.0);
  base.go(first.data(), first.size(), 0.0);
  EXPECT_TRUE(base.on_timetable());
  for (double t : {0.0, 5.0, 14.5, 20.0, 28.9}) {
    base.update(t);
    EXPECT_EQ(base.pose().x, route.position(t).x) << t;
    EXPECT_EQ(base.pose().y, route.position(t).y) << t;
  }
  EXPECT_EQ(base.state(), NavState::kActive);
  base.update(route.period() + 0.05);
  EXPECT_EQ(base.state(), NavState::kReached);
  EXPECT_EQ(base.legs_done(), first.size());
  EXPECT_DOUBLE_EQ(base.arrived_at(first.size() - 1), first.back().arrive);
  // The next loop, on time: its timetable again.
  const double next = route.schedule().next_departure(route.period());
  const std::vector<Waypoint> second = loop(route, next);
  base.update(next + 0.03);
  base.go(second.data(), second.size(), next + 0.03);
  EXPECT_TRUE(base.on_timetable());
  base.update(next + 7.0);
  EXPECT_EQ(base.pose().x, route.position(next + 7.0).x);
}

TEST(RouteBase, ALateLoopIsDrivenStraightAtThePlannedPace) {
  CorridorTeam c;
  const mission::RouteTimetable& route = c.team->routes[CollectorId(0)];
  RouteBase base(route, Point2{0.55, 0.25}, route.waypoints().size());
  std::vector<Waypoint> legs = loop(route, 0.0);
  for (Waypoint& w : legs) w.arrive += 2.0;  // not the timetable's times: a command like any other
  base.go(legs.data(), legs.size(), 2.0);
  EXPECT_FALSE(base.on_timetable());
  base.update(legs[0].arrive);
  EXPECT_EQ(base.legs_done(), 1u);
  EXPECT_NEAR(base.pose().x, legs[0].point.x, 1e-9);
  base.stop(legs[0].arrive);
  base.update(legs[0].arrive + 10.0);
  EXPECT_EQ(base.state(), NavState::kIdle);
  EXPECT_NEAR(base.pose().x, legs[0].point.x, 1e-9);  // stopped: it stays
  EXPECT_THROW(base.go(legs.data(), 0, 0.0), Error);
}

}  // namespace
}  // namespace agent
}  // namespace gather
