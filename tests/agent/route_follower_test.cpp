// motion/route_follower: a collector is where its timetable says, at every
// instant, and takes no legs.
#include "gather_agent/motion/route_follower.hpp"

#include <gtest/gtest.h>

#include "corridor_team.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;

TEST(RouteFollower, IsWhereItsTimetableSaysAndHoldsWhenTold) {
  CorridorTeam c;
  const mission::RouteTimetable& route = c.team->routes[CollectorId(0)];
  RouteFollower base(Point2{0.55, 0.25});
  base.advance(3.0);
  EXPECT_DOUBLE_EQ(base.pose().x, 0.55);  // no route yet: where it started
  base.follow(route);
  for (double t : {0.0, 5.0, 14.5, 20.0, 28.9, 57.0}) {
    base.advance(t);
    EXPECT_DOUBLE_EQ(base.pose().x, route.position(t).x) << t;
    EXPECT_DOUBLE_EQ(base.pose().y, route.position(t).y) << t;
  }
  base.advance(10.0);
  const Point2 at = base.pose();
  base.hold();
  base.advance(20.0);
  EXPECT_DOUBLE_EQ(base.pose().x, at.x);  // held: it stays
  const Waypoint leg{Point2{1.0, 0.25}, 1.0};
  EXPECT_THROW(base.go(&leg, 1, 0.0), Error);
  EXPECT_EQ(base.max_legs(), 0u);
}

}  // namespace
}  // namespace agent
}  // namespace gather
