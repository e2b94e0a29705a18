// robot_bridge's decisions (gather_oc/nav_bridge.hpp): an agent's command
// goes to move_base one waypoint at a time; a waypoint counts when the pose
// is within its tolerance or move_base says the goal succeeded; move_base
// giving up is FAILED at that waypoint; no progress is BLOCKED; STOP cancels.
#include <gtest/gtest.h>

#include <cmath>

#include "gather_oc/nav_bridge.hpp"

namespace gather {
namespace oc {
namespace {

using agent::NavCommand;
using agent::NavState;
using Kind = MoveBaseOrder::Kind;

NavCommand go(int id, std::initializer_list<Point2> points, double tolerance = 0.25) {
  NavCommand c;
  c.agent = 3, c.id = id, c.kind = NavCommand::Kind::kGo;
  for (Point2 p : points) {
    c.points[c.n] = p, c.after[c.n] = 10.0 * (c.n + 1), c.tolerance[c.n] = tolerance;
    ++c.n;
  }
  return c;
}

TEST(NavBridge, WaypointsGoOneByOneAndCountByPoseOrByMoveBase) {
  NavBridge b(3);
  b.pose({0, 0}, 0.0, 1.0);
  MoveBaseOrder o = b.command(go(1, {{2, 0}, {2, 2}, {0, 2}}), 1.0);
  ASSERT_EQ(o.kind, Kind::kGoal);
  EXPECT_EQ(o.at.x, 2.0);
  EXPECT_NEAR(o.yaw, M_PI / 2, 1e-9);  // arriving headed to the next waypoint
  EXPECT_EQ(b.status().state, NavState::kActive);
  EXPECT_EQ(b.status().command, 1);
  EXPECT_TRUE(b.take_changed());
  EXPECT_FALSE(b.take_changed());
  EXPECT_EQ(b.command(go(1, {{2, 0}, {2, 2}, {0, 2}}), 1.5).kind, Kind::kNone);  // a repeat
  EXPECT_EQ(b.pose({1.0, 0.0}, 0.0, 2.0).kind, Kind::kNone);
  EXPECT_NEAR(b.robot_pose().v, 1.0, 1e-9);
  o = b.pose({1.8, 0.0}, 0.0, 3.0);  // within 0.25 m: reached, on to the next
  ASSERT_EQ(o.kind, Kind::kGoal);
  EXPECT_EQ(o.at.y, 2.0);
  EXPECT_EQ(b.status().reached, 1);
  EXPECT_EQ(b.status().reached_at[0], 3.0);
  // move_base: an older goal's status is not about this one; this one's success counts.
  EXPECT_EQ(b.goal_status(GoalStatus::kSucceeded, 1.0, 3.5).kind, Kind::kNone);
  EXPECT_EQ(b.status().reached, 1);
  o = b.goal_status(GoalStatus::kSucceeded, 3.01, 4.0);
  ASSERT_EQ(o.kind, Kind::kGoal);
  EXPECT_EQ(o.at.x, 0.0);
  EXPECT_NEAR(o.yaw, M_PI, 1e-9);  // the last: as it came
  EXPECT_EQ(b.status().reached, 2);
  b.pose({0.1, 2.0}, M_PI, 5.0);
  EXPECT_EQ(b.status().state, NavState::kReached);
  EXPECT_EQ(b.status().reached, 3);
  EXPECT_EQ(b.status().reached_at[2], 5.0);
  EXPECT_EQ(b.goals_sent(), 3);
}

TEST(NavBridge, MoveBaseGivingUpIsFailedAtThatWaypoint) {
  for (GoalStatus s : {GoalStatus::kAborted, GoalStatus::kRejected, GoalStatus::kPreempted, GoalStatus::kLost}) {
    NavBridge b(0);
    b.pose({0, 0}, 0.0, 1.0);
    b.command(go(4, {{0.1, 0}, {5, 0}}), 1.0);  // stands on the first: it counts at once
    EXPECT_EQ(b.status().reached, 1);
    b.goal_status(GoalStatus::kActive, 1.0, 1.5);
    EXPECT_EQ(b.status().state, NavState::kActive);
    b.goal_status(s, 1.0, 2.0);
    EXPECT_EQ(b.status().state, NavState::kFailed) << static_cast<int>(s);
    EXPECT_EQ(b.status().reached, 1);
    EXPECT_EQ(b.tick(10.0).kind, Kind::kNone);  // nothing goes out again
  }
}

TEST(NavBridge, NoProgressIsBlockedUntilItMovesAndAnUnheardGoalGoesOutAgain) {
  NavBridge b(0);
  b.pose({0, 0}, 0.0, 0.0);
  b.command(go(1, {{10, 0}}), 0.0);
  EXPECT_EQ(b.tick(1.0).kind, Kind::kNone);
  EXPECT_EQ(b.tick(2.5).kind, Kind::kGoal);  // move_base never reported it
  b.goal_status(GoalStatus::kActive, 2.5, 2.6);
  EXPECT_EQ(b.tick(6.0).kind, Kind::kNone);  // heard: no resend
  b.pose({0.01, 0}, 0.0, 4.0);
  EXPECT_EQ(b.status().state, NavState::kActive);
  b.pose({0.02, 0}, 0.0, 5.5);
  EXPECT_EQ(b.status().state, NavState::kBlocked);
  b.pose({0.5, 0}, 0.0, 6.0);
  EXPECT_EQ(b.status().state, NavState::kActive);
}

TEST(NavBridge, StopCancelsAndIsIdle) {
  NavBridge b(0);
  b.pose({0, 0}, 0.0, 0.0);
  b.command(go(1, {{10, 0}}), 0.0);
  NavCommand stop;
  stop.id = 2, stop.kind = NavCommand::Kind::kStop;
  EXPECT_EQ(b.command(stop, 1.0).kind, Kind::kCancel);
  EXPECT_EQ(b.status().state, NavState::kIdle);
  EXPECT_EQ(b.status().command, 2);
  EXPECT_EQ(b.goal_status(GoalStatus::kAborted, 5.0, 5.0).kind, Kind::kNone);  // the cancelled goal's end
  EXPECT_EQ(b.status().state, NavState::kIdle);
  EXPECT_EQ(b.tick(10.0).kind, Kind::kNone);
}

}  // namespace
}  // namespace oc
}  // namespace gather
