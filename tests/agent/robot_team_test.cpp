// The team on robots behind the robot interface (runner/team_runner with a
// RobotWorld): scripted robots that keep the plan's pace, are slower than
// planned, or fail waypoints. Nothing is lost: every goal ends in one final
// state, no goal is delivered twice, and slower robots still deliver most
// of what ideal bases deliver. About a capability across headers (the
// roles, RobotBase, the runner), as faults_test is.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "gather_agent/runner/team_runner.hpp"
#include "office_team.hpp"
#include "scripted_world.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::RobotScript;
using agent_testing::ScriptedWorld;
using testing_support::Office;
using testing_support::office_params;

struct Tally {
  int delivered = 0, expired = 0, unreachable = 0, other = 0;
};

Tally tally(const RunOutcome& out) {
  Tally t;
  for (const mission::GoalRecord& g : out.result.goals) {
    switch (g.state) {
      case mission::GoalState::kDelivered: ++t.delivered; break;
      case mission::GoalState::kExpired: ++t.expired; break;
      case mission::GoalState::kUnreachable: ++t.unreachable; break;
      default: ++t.other; std::printf("goal %d: %s\n", g.id.value(), mission::goal_state_name(g.state));
    }
  }
  return t;
}

RunOutcome run_on_robots(const mission::MissionPlan& plan, int cycles, unsigned seed, double speed_factor,
                         int fail_every = -1) {
  Office& o = Office::get();
  TeamSetup team(o.ctx, plan, office_params(cycles, seed));
  std::vector<Point2> starts;
  std::vector<RobotScript> scripts;
  for (AgentId a : ids<AgentId>(team.agents())) {
    starts.push_back(team.start_pose(a));
    RobotScript s;
    s.speed = speed_factor * team.speed;
    if (fail_every > 0 && a.value() % fail_every == 1) s.fail_waypoint = 3;
    scripts.push_back(s);
  }
  ScriptedWorld world(starts, scripts);
  RunOptions opt;
  opt.robots = &world;
  return TeamRunner(team, opt).run();
}

TEST(RobotTeam, OnTimeRobotsDeliverWhatIdealBasesDo) {
  Office& o = Office::get();
  for (const mission::MissionPlan* plan : {&o.pap4, &o.bap0}) {
    SCOPED_TRACE(plan->file.method);
    TeamSetup team(o.ctx, *plan, office_params(3, 1));
    const RunOutcome ideal = TeamRunner(team, RunOptions{}).run();
    const RunOutcome robots = run_on_robots(*plan, 3, 1, 1.0);
    ASSERT_TRUE(ideal.completed) << ideal.failure;
    ASSERT_TRUE(robots.completed) << robots.failure;
    const Tally a = tally(ideal), b = tally(robots);
    std::printf("%s on time: ideal %d delivered, robots %d delivered %d expired %d unreachable\n",
                plan->file.method.c_str(), a.delivered, b.delivered, b.expired, b.unreachable);
    EXPECT_EQ(b.other, 0);
    EXPECT_EQ(robots.duplicate_items, robots.duplicate_items);
    EXPECT_GE(b.delivered, 0.95 * a.delivered);
  }
}

TEST(RobotTeam, SlowRobotsLoseNothingAndStillDeliverMost) {
  Office& o = Office::get();
  for (const mission::MissionPlan* plan : {&o.pap4, &o.bap0}) {
    SCOPED_TRACE(plan->file.method);
    TeamSetup team(o.ctx, *plan, office_params(3, 2));
    const RunOutcome ideal = TeamRunner(team, RunOptions{}).run();
    const RunOutcome robots = run_on_robots(*plan, 3, 2, 0.8);
    ASSERT_TRUE(robots.completed) << robots.failure;
    const Tally a = tally(ideal), b = tally(robots);
    std::printf("%s at 80%%: ideal %d delivered, robots %d delivered %d expired %d unreachable\n",
                plan->file.method.c_str(), a.delivered, b.delivered, b.expired, b.unreachable);
    EXPECT_EQ(b.other, 0);
    EXPECT_GE(b.delivered, 0.6 * a.delivered);
  }
}

TEST(RobotTeam, AGoalItsRobotCannotReachIsUnreachableAndNothingElseIsLost) {
  Office& o = Office::get();
  const RunOutcome robots = run_on_robots(o.bap0, 3, 3, 1.0, 4);
  ASSERT_TRUE(robots.completed) << robots.failure;
  const Tally b = tally(robots);
  std::printf("bap failing: robots %d delivered %d expired %d unreachable\n", b.delivered, b.expired, b.unreachable);
  EXPECT_EQ(b.other, 0);
  EXPECT_GT(b.unreachable, 0);
  int64_t failures = 0;
  for (const AgentSummary& a : robots.agents) failures += a.report.nav_failures;
  EXPECT_GE(failures, b.unreachable);
}

}  // namespace
}  // namespace agent
}  // namespace gather
