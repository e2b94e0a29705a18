// motion/robot_base: the agent's side of the robot interface against
// scripted robots: waypoints count when the robot says so, at the time it
// says; a late robot is late, a failed waypoint is reported, a silent robot
// and a pose off the map or not a number are faults (with one line), a
// status about another command or one that goes back is dropped and counted.
#include "gather_agent/motion/robot_base.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../core/corridor.hpp"
#include "gather_core/error.hpp"
#include "scripted_world.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::RobotScript;
using agent_testing::ScriptedRobot;

// One robot on the corridor and its base, stepped together every 0.1 s.
struct Rig {
  Scenario scenario = testing_support::corridor();
  CommandQueue queue;
  RobotBase base;
  ScriptedRobot robot;
  double t = 0.0;
  int64_t tick = 0;
  explicit Rig(RobotScript script, RobotBaseParams params = {})
      : base(scenario.grid, 3, Point2{0.55, 0.25}, 1.0, queue, params), robot(3, Point2{0.55, 0.25}, script) {}
  void run_until(double until) {
    for (; t <= until + 1e-9; t = ++tick * 0.1) {
      for (const NavCommand& c : queue.commands) robot.command(c);
      queue.commands.clear();
      robot.step(t);
      if (robot.talks(t)) {
        base.on_pose(robot.pose(tick), t);
        base.on_status(robot.status(tick), t);
      }
      base.update(t);
    }
  }
};

TEST(RobotBase, AWaypointCountsWhenTheRobotSaysAtTheTimeItSays) {
  Rig r(RobotScript{0.5});  // half the team speed
  r.run_until(1.0);
  EXPECT_NEAR(r.base.pose().x, 0.55, 1e-9);   // no command yet
  const Waypoint w{Point2{3.55, 0.25}, 4.0};  // 3 m in 3 s from t = 1
  r.base.go(&w, 1, 1.0);
  ASSERT_EQ(r.queue.commands.size(), 1u);
  EXPECT_EQ(r.queue.commands[0].kind, NavCommand::Kind::kGo);
  EXPECT_NEAR(r.queue.commands[0].after[0], 3.0, 1e-12);
  r.run_until(4.5);
  EXPECT_EQ(r.base.state(), NavState::kActive);  // planned at 4 s: it is not there yet
  EXPECT_EQ(r.base.legs_done(), 0u);
  EXPECT_NEAR(r.base.arrival_estimate(), 7.0, 1e-9);  // the robot's own estimate: 3 m at 0.5 m/s from 1 s
  r.run_until(8.0);
  EXPECT_EQ(r.base.state(), NavState::kReached);
  ASSERT_EQ(r.base.legs_done(), 1u);
  EXPECT_NEAR(r.base.arrived_at(0), 7.0, 1e-9);  // when the robot got there: late by 3 s
  EXPECT_NEAR(r.base.pose().x, 3.55, 1e-9);
  EXPECT_EQ(r.base.fault(), BaseFault::kNone);
  r.base.stop(8.0);
  r.run_until(9.0);
  EXPECT_EQ(r.base.state(), NavState::kIdle);
}

TEST(RobotBase, AWaypointTheRobotGivesUpIsAFailedCommand) {
  RobotScript s;
  s.fail_waypoint = 1;
  Rig r(s);
  const Waypoint w[2] = {{Point2{2.05, 0.25}, 2.0}, {Point2{4.05, 0.25}, 4.0}};
  r.base.go(w, 2, 0.0);
  r.run_until(6.0);
  EXPECT_EQ(r.base.state(), NavState::kFailed);
  EXPECT_EQ(r.base.legs_done(), 1u);  // the first one was reached
  EXPECT_EQ(r.base.fault(), BaseFault::kNone);
}

TEST(RobotBase, ARobotThatFallsSilentIsAFaultWithOneLine) {
  RobotScript s;
  s.silent_from = 2.0;
  RobotBaseParams p;
  p.silence_s = 1.0;
  Rig r(s, p);
  const Waypoint w{Point2{10.05, 0.25}, 10.0};
  r.base.go(&w, 1, 0.0);
  r.run_until(2.8);
  EXPECT_EQ(r.base.fault(), BaseFault::kNone);  // last heard at 1.9 s
  r.run_until(3.2);
  EXPECT_EQ(r.base.fault(), BaseFault::kSilent);
  EXPECT_NE(r.base.fault_text().find("robot silent at t = "), std::string::npos) << r.base.fault_text();
  EXPECT_NE(r.base.fault_text().find("no pose or status"), std::string::npos) << r.base.fault_text();
  EXPECT_EQ(r.base.counters().faults, 1);
  const double x = r.base.pose().x;
  r.run_until(5.0);
  EXPECT_EQ(r.base.pose().x, x);             // where it was last heard of
  EXPECT_GT(r.base.counters().commands, 3);  // the command went out again and again
}

TEST(RobotBase, ARobotThatNeverAnswersACommandIsSilent) {
  Scenario scenario = testing_support::corridor();
  CommandQueue queue;
  RobotBase base(scenario.grid, 0, Point2{0.55, 0.25}, 1.0, queue);
  const Waypoint w{Point2{3.05, 0.25}, 3.0};
  base.go(&w, 1, 0.0);
  for (double t = 0.0; t < 2.5; t += 0.1) base.update(t);
  EXPECT_EQ(base.fault(), BaseFault::kSilent);
  EXPECT_EQ(base.legs_done(), 0u);
}

TEST(RobotBase, APoseOffTheMapOrNotANumberIsAFaultAndNotTaken) {
  RobotScript s;
  s.nan_from = 1.0;
  s.off_map_from = 2.0;
  Rig r(s);
  const Waypoint w{Point2{10.05, 0.25}, 10.0};
  r.base.go(&w, 1, 0.0);
  r.run_until(1.5);
  EXPECT_EQ(r.base.fault(), BaseFault::kOffMap);
  EXPECT_TRUE(std::isfinite(r.base.pose().x));
  EXPECT_NEAR(r.base.pose().x, 1.45, 0.11);  // the last good pose (t = 0.9 s)
  r.run_until(2.5);
  EXPECT_EQ(r.base.fault(), BaseFault::kOffMap);
  EXPECT_GT(r.base.pose().x, 0.0);  // never the far-off one
  EXPECT_GE(r.base.counters().bad_pose, 15);
  EXPECT_EQ(r.base.counters().faults, 1);  // one fault: the robot never came back
  EXPECT_NE(r.base.first_fault().find("off_map"), std::string::npos) << r.base.first_fault();
}

TEST(RobotBase, AStatusAboutAnotherCommandOrThatGoesBackIsDropped) {
  Scenario scenario = testing_support::corridor();
  CommandQueue queue;
  RobotBase base(scenario.grid, 0, Point2{0.55, 0.25}, 1.0, queue);
  const Waypoint w[2] = {{Point2{2.05, 0.25}, 2.0}, {Point2{4.05, 0.25}, 4.0}};
  base.go(w, 2, 0.0);
  NavStatus s;
  s.agent = 0, s.stamp = 1.0, s.command = 99, s.state = NavState::kReached, s.reached = 2;
  s.reached_at[0] = 0.5, s.reached_at[1] = 0.9;
  base.on_status(s, 1.0);
  EXPECT_EQ(base.counters().stale_status, 1);
  EXPECT_EQ(base.state(), NavState::kActive);
  s.command = queue.commands.back().id;
  s.reached = 1, s.state = NavState::kActive;
  base.on_status(s, 1.0);
  EXPECT_EQ(base.legs_done(), 1u);
  s.reached = 0;  // goes back on what it said
  base.on_status(s, 1.1);
  s.reached = 3;  // more than the command has
  base.on_status(s, 1.2);
  s.reached = 2, s.reached_at[1] = 5.0;  // reached after its own stamp
  base.on_status(s, 1.3);
  EXPECT_EQ(base.counters().bad_status, 3);
  EXPECT_EQ(base.legs_done(), 1u);
}

TEST(RobotBase, ItsParametersHaveRanges) {
  Scenario scenario = testing_support::corridor();
  CommandQueue queue;
  RobotBaseParams p;
  p.silence_s = 0.0;
  try {
    RobotBase base(scenario.grid, 0, Point2{0.55, 0.25}, 1.0, queue, p);
    FAIL() << "silence_s 0 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("silence_s = 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace agent
}  // namespace gather
