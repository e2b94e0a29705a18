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
  EXPECT_EQ(b.goal_status({{"mb-1", 1.0, GoalStatus::kSucceeded}}, 3.5).kind, Kind::kNone);
  EXPECT_EQ(b.status().reached, 1);
  o = b.goal_status({{"mb-1", 1.0, GoalStatus::kPreempted}, {"mb-2", 3.01, GoalStatus::kSucceeded}}, 4.0);
  ASSERT_EQ(o.kind, Kind::kGoal);
  EXPECT_EQ(o.at.x, 0.0);
  EXPECT_NEAR(o.yaw, M_PI, 1e-9);  // the last: as it came
  EXPECT_EQ(b.status().reached, 2);
  b.goal_status({{"mb-3", 4.01, GoalStatus::kActive}}, 4.5);
  o = b.pose({0.1, 2.0}, M_PI, 5.0);  // within the last one's tolerance: stop there
  EXPECT_EQ(o.kind, Kind::kCancel);
  EXPECT_EQ(o.goal_id, "mb-3");
  EXPECT_EQ(b.status().state, NavState::kReached);
  EXPECT_EQ(b.status().reached, 3);
  EXPECT_EQ(b.status().reached_at[2], 5.0);
  EXPECT_EQ(b.goals_sent(), 3);
}

TEST(NavBridge, MoveBaseGivingUpIsFailedAtThatWaypoint) {
  for (GoalStatus s : {GoalStatus::kAborted, GoalStatus::kRejected, GoalStatus::kPreempted, GoalStatus::kRecalled,
                       GoalStatus::kLost}) {
    NavBridge b(0);
    b.pose({0, 0}, 0.0, 1.0);
    b.command(go(4, {{0.1, 0}, {5, 0}}), 1.0);  // stands on the first: it counts at once
    EXPECT_EQ(b.status().reached, 1);
    b.goal_status({{"mb-7", 1.0, GoalStatus::kActive}}, 1.5);
    EXPECT_EQ(b.status().state, NavState::kActive);
    b.goal_status({{"mb-7", 1.0, s}}, 2.0);
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
  b.goal_status({{"mb-1", 2.5, GoalStatus::kActive}}, 2.6);
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
  EXPECT_EQ(b.goal_status({{"mb-1", 0.0, GoalStatus::kAborted}}, 5.0).kind, Kind::kNone);  // the cancelled goal's end
  EXPECT_EQ(b.status().state, NavState::kIdle);
  EXPECT_EQ(b.tick(10.0).kind, Kind::kNone);
}

// Someone else's goal (RViz, a teleop tool) takes move_base over: its
// success is not ours; ours is FAILED at the waypoint it was driving to.
TEST(NavBridge, SomeoneElsesNewerGoalIsNeverOursAndEndsOurCommand) {
  NavBridge b(0);
  b.pose({0, 0}, 0.0, 0.0);
  b.command(go(1, {{10, 0}, {20, 0}}), 0.0);
  b.goal_status({{"ours", 0.01, GoalStatus::kActive}}, 0.5);
  EXPECT_EQ(b.status().state, NavState::kActive);
  b.goal_status({{"ours", 0.01, GoalStatus::kPreempted}, {"rviz", 1.0, GoalStatus::kActive}}, 1.5);
  EXPECT_EQ(b.status().state, NavState::kFailed);
  EXPECT_EQ(b.status().reached, 0);
  NavBridge c(0);  // the other goal succeeds first: still not ours
  c.pose({0, 0}, 0.0, 0.0);
  c.command(go(1, {{10, 0}}), 0.0);
  c.goal_status({{"ours", 0.01, GoalStatus::kActive}}, 0.5);
  c.goal_status({{"ours", 0.01, GoalStatus::kActive}, {"rviz", 1.0, GoalStatus::kSucceeded}}, 1.5);
  EXPECT_EQ(c.status().reached, 0);
  EXPECT_NE(c.status().state, NavState::kReached);
}

// A new command whose waypoints the robot already stands on: the goal of
// the command before must not go on driving it away.
TEST(NavBridge, ANewCommandAlreadyReachedStopsTheGoalBefore) {
  NavBridge b(0);
  b.pose({0, 0}, 0.0, 0.0);
  b.command(go(1, {{10, 0}}), 0.0);
  b.goal_status({{"mb-1", 0.01, GoalStatus::kActive}}, 0.5);
  const MoveBaseOrder o = b.command(go(2, {{0.1, 0.0}}), 1.0);
  EXPECT_EQ(o.kind, Kind::kCancel);
  EXPECT_EQ(o.goal_id, "mb-1");
  EXPECT_EQ(b.status().state, NavState::kReached);
  EXPECT_EQ(b.status().reached, 1);
}

}  // namespace
}  // namespace oc
}  // namespace gather
