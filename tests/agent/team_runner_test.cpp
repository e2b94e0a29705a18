// runner/team_runner: the whole team in one process, on the corridor against
// hand-computed times and on maps/office against the analytic simulator
// (the equivalence guard), deterministic, with lossy radio and small buffers.
#include "gather_agent/runner/team_runner.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "corridor_team.hpp"
#include "gather_core/mission/simulator.hpp"
#include "office_team.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;
using agent_testing::measured;
using agent_testing::message;
using agent_testing::request;
using gather::testing_support::corridor;
using gather::testing_support::corridor_plan;

// The whole team on the corridor: the simulator's hand-computed times
// (tests/core/simulator_test.cpp) up to the tick and message latencies.
TEST(TeamRunner, CorridorTimesAreTheSimulatorsUpToTicks) {
  CorridorTeam c(2, {{0, Point2{5.05, 0.25}}, {0, Point2{17.05, 0.25}}, {1, Point2{19.05, 0.25}}});
  const RunOutcome out = TeamRunner(*c.team, RunOptions{}).run();
  ASSERT_TRUE(out.completed) << out.failure;
  const double range = RadioModel(c.scenario.grid, c.scenario.radio).free_space_range();
  const auto& g = out.result.goals;
  ASSERT_EQ(g.size(), 3u);
  // The simulator's workers start at the OC (x = 0.55 m); this one at its
  // start pose, and hears request 0 a tick after it is issued.
  const double start = 0.1 - (c.team->start_pose(AgentId(1)).x - 0.55);
  EXPECT_NEAR(g[0].measured_at, 4.5 + start, 0.15);
  EXPECT_NEAR(g[0].picked_up_at, g[0].measured_at, 0.3);
  EXPECT_NEAR(g[0].delivered_at, 26.95, 0.3);
  EXPECT_NEAR(g[1].measured_at, 16.5 + start, 0.15);
  EXPECT_NEAR(g[1].picked_up_at, 43.5 - range, 0.3);
  EXPECT_NEAR(g[1].delivered_at, 55.95, 0.3);
  EXPECT_NEAR(g[2].measured_at, 118.5, 0.3);  // it waited at the meeting point: request 1 arrives at 114.5 s
  EXPECT_NEAR(g[2].picked_up_at, 143.5 - range, 0.3);
  EXPECT_NEAR(g[2].delivered_at, 155.95, 0.3);
  for (const auto& x : g) EXPECT_EQ(x.state, mission::GoalState::kDelivered);
  EXPECT_EQ(out.agents[1].report.measured, 3);
  EXPECT_GT(out.agents[1].link.gated, 0);  // out of the OC's range most of the time
}

// Hand-overs that take time (the lingering strip, one goal = 10 s of link):
// the agents hand over when the simulator does, up to ticks and message
// latencies, and the second goal waits for the first to be gone.
TEST(TeamRunner, HandOverTakesItsTransferTimeAsInTheSimulator) {
  const Scenario s = testing_support::lingering_strip();
  const mission::World world(s);
  const mission::MissionPlan p = testing_support::lingering_plan(s);
  MissionParams prm;
  prm.cycles = 1, prm.goals_per_request = 2;
  prm.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{7.05, 0.25}}};
  TeamSetup team(world, p, prm);
  const RunOutcome out = TeamRunner(team, RunOptions{}).run();
  ASSERT_TRUE(out.completed) << out.failure;
  const auto& g = out.result.goals;
  ASSERT_EQ(g.size(), 2u);
  const double start = 0.1 - (team.start_pose(AgentId(1)).x - 0.55);
  EXPECT_NEAR(g[0].measured_at, 4.5 + start, 0.15);
  EXPECT_NEAR(g[0].picked_up_at, g[0].measured_at + 10.0, 0.3);  // the simulator: 14.5 s
  EXPECT_GT(g[1].measured_at, g[0].picked_up_at);
  for (const auto& x : g) EXPECT_EQ(x.state, mission::GoalState::kDelivered);
}

TEST(TeamRunner, RequestsArrivingTogetherLeaveOnlyTheNewest) {
  // As the simulator's test: T = 10 s, route 29 s. Requests 1 and 2 reach
  // the worker together at 43.5 s; request 1 is skipped, its goal expires.
  Scenario s = corridor();
  s.mission.period = 10.0;
  const mission::World world(s);
  const mission::MissionPlan p = corridor_plan(s);
  MissionParams prm;
  prm.cycles = 2, prm.goals_per_request = 2;
  prm.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{17.05, 0.25}}, {1, Point2{5.05, 0.25}}};
  TeamSetup team(world, p, prm);
  const RunOutcome out = TeamRunner(team, RunOptions{}).run();
  ASSERT_TRUE(out.completed) << out.failure;
  EXPECT_EQ(out.result.goals[0].state, mission::GoalState::kDelivered);
  // Request 0 is valid for one period (mission::request_deadline): the goal
  // 12 m further than the first expires at 10 s, as in the simulator.
  EXPECT_EQ(out.result.goals[1].state, mission::GoalState::kExpired);
  EXPECT_NEAR(out.result.goals[1].expired_at, 10.0, 1e-6);
  EXPECT_EQ(out.result.goals[2].state, mission::GoalState::kExpired);
  EXPECT_NEAR(out.result.goals[2].expired_at, 43.5, 1e-6);
  EXPECT_EQ(out.agents[1].report.skipped, 1);
}

TEST(TeamRunner, OneExpiryRuleForWorkersOfTheOcToo) {
  // As the simulator's test: the corridor without its collector, T = 10 s.
  // The OC worker knows request 0 at t = 0, measures the goal at 4.5 s; the
  // one it would reach at 18.5 s expires at 10 s, one period after it
  // learned the request (mission::request_deadline).
  Scenario s = corridor();
  s.mission.period = 10.0;
  s.team.agents = 1;
  const mission::World world(s);
  const mission::MissionPlan p = testing_support::corridor_plan_without_collector(s);
  MissionParams prm;
  prm.cycles = 1, prm.goals_per_request = 2;
  prm.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{19.05, 0.25}}};
  TeamSetup team(world, p, prm);
  const RunOutcome out = TeamRunner(team, RunOptions{}).run();
  ASSERT_TRUE(out.completed) << out.failure;
  ASSERT_EQ(out.result.goals.size(), 2u);
  EXPECT_EQ(out.result.goals[0].state, mission::GoalState::kDelivered);
  EXPECT_EQ(out.result.goals[1].state, mission::GoalState::kExpired);
  EXPECT_NEAR(out.result.goals[1].expired_at, 10.0, 0.11);  // within a tick
}

using testing_support::Office;
using testing_support::office_params;

// The guard of "one protocol": the agents and the analytic simulator, same
// plans and seeds, agree within 5% on refresh time and goals per cycle.
TEST(TeamRunner, OfficeAgreesWithTheAnalyticSimulatorWithinFivePercent) {
  Office& o = Office::get();
  for (const mission::MissionPlan* plan : {&o.pap4, &o.bap0}) {
    mission::MissionSimulator sim(o.ctx, *plan);
    double r_sim = 0, g_sim = 0, r_run = 0, g_run = 0;
    for (unsigned seed = 1; seed <= 3; ++seed) {
      mission::MissionOptions mo;
      mo.cycles = 10, mo.seed = seed;
      const auto s = sim.run(mo);
      r_sim += s.refresh_mean_s, g_sim += s.goals_per_cycle;
      TeamSetup team(o.ctx, *plan, office_params(10, seed));
      const RunOutcome out = TeamRunner(team, RunOptions{}).run();
      ASSERT_TRUE(out.completed) << out.failure;
      r_run += out.result.refresh_mean_s, g_run += out.result.goals_per_cycle;
    }
    SCOPED_TRACE(plan->file.method + ":" + std::to_string(plan->file.collectors));
    EXPECT_NEAR(r_run / r_sim, 1.0, 0.05) << "refresh: agents " << r_run / 3 << " s, simulator " << r_sim / 3 << " s";
    EXPECT_NEAR(g_run / g_sim, 1.0, 0.05) << "goals per cycle: agents " << g_run / 3 << ", simulator " << g_sim / 3;
  }
}

// A plan whose period was cut far below its own (a hand-edited plan.yaml):
// workers stay out of the coverage for longer than a few periods, so the
// run waits for them as long as the way to the farthest cell and back
// takes. It used to stop at (cycles + 5) periods with goals unresolved
// (exit 1): neither a result nor a refusal.
TEST(TeamRunner, APeriodFarShorterThanThePlansStillEndsWithEveryGoalResolved) {
  Office& o = Office::get();
  // pap:4 as `gather plan --config pap:4` makes it (the association on).
  const mission::MissionPlan pap4 =
      mission::mission_plan(o.ctx, plan::plan_configuration(o.ctx, partition::Method::kPap, 4));
  for (const double period : {5.0, 1.0}) {
    mission::MissionPlan plan = pap4;
    plan.file.cycle_period_s = period;
    TeamSetup team(o.ctx, plan, office_params(2, 1));
    const RunOutcome out = TeamRunner(team, RunOptions{}).run();
    ASSERT_TRUE(out.completed) << period << ": " << out.failure;
    for (const auto& g : out.result.goals) EXPECT_NE(g.state, mission::GoalState::kPending) << period;
  }
}

TEST(TeamRunner, DeterministicForASeedAndTheSeedMatters) {
  Office& o = Office::get();
  auto run = [&](unsigned seed) {
    TeamSetup team(o.ctx, o.pap4, office_params(3, seed));
    return TeamRunner(team, RunOptions{}).run();
  };
  const RunOutcome a = run(3), b = run(3), c = run(4);
  ASSERT_TRUE(a.completed && b.completed && c.completed);
  ASSERT_EQ(a.result.goals.size(), b.result.goals.size());
  bool differ = false;
  for (std::size_t i = 0; i < a.result.goals.size(); ++i) {
    EXPECT_EQ(a.result.goals[i].delivered_at, b.result.goals[i].delivered_at);
    EXPECT_EQ(a.result.goals[i].measured_at, b.result.goals[i].measured_at);
    differ = differ || a.result.goals[i].point.x != c.result.goals[i].point.x;
  }
  EXPECT_EQ(a.messages, b.messages);
  EXPECT_TRUE(differ);
}

TEST(TeamRunner, LossyRadioLosesNoDataAndResends) {
  // With and without collectors (workers of the OC ask again for a request
  // whose broadcast they lost; the OC answers their beacons too).
  Office& o = Office::get();
  for (const mission::MissionPlan* plan : {&o.pap4, &o.bap0}) {
    SCOPED_TRACE(plan->file.method);
    TeamSetup team(o.ctx, *plan, office_params(4, 2));
    RunOptions opt;
    opt.loss = 0.3, opt.loss_seed = 5;
    const RunOutcome out = TeamRunner(team, opt).run();  // checks conservation at every cycle's end
    ASSERT_TRUE(out.completed) << out.failure;
    int64_t measured = 0, lost = 0, delivered = 0, dropped = 0;
    for (const AgentSummary& a : out.agents) measured += a.report.measured, lost += a.link.lost;
    for (const auto& g : out.result.goals) {
      delivered += g.state == mission::GoalState::kDelivered;
      dropped += g.state == mission::GoalState::kDropped;
    }
    EXPECT_GT(lost, 50);             // of the messages each receiver hears (its links': FleetLinks)
    EXPECT_EQ(measured, delivered);  // every measured goal reached the OC
    EXPECT_EQ(dropped, 0);
    EXPECT_GT(out.duplicate_items, 0);  // lost acks: resent, counted once
  }
}

TEST(TeamRunner, HeavyLossStillResolvesEveryGoal) {
  Office& o = Office::get();
  for (const mission::MissionPlan* plan : {&o.pap4, &o.bap0}) {
    TeamSetup team(o.ctx, *plan, office_params(3, 4));
    RunOptions opt;
    opt.loss = 0.6, opt.loss_seed = 9;
    const RunOutcome out = TeamRunner(team, opt).run();
    EXPECT_TRUE(out.completed) << plan->file.method << ": " << out.failure;
  }
}

TEST(TeamRunner, ABufferTooSmallDropsWithAReasonAndNeverSilently) {
  Office& o = Office::get();
  MissionParams p = office_params(4, 1);
  p.data_capacity = 1;
  p.notice_capacity = 1000;
  TeamSetup team(o.ctx, o.pap4, p);
  const RunOutcome out = TeamRunner(team, RunOptions{}).run();
  ASSERT_TRUE(out.completed) << out.failure;
  int64_t dropped = 0, measured = 0, refused = 0, requested = 0, resolved = 0;
  for (const AgentSummary& a : out.agents) measured += a.report.measured, refused += a.report.refused_full;
  for (const auto& g : out.result.goals) {
    ++requested;
    dropped += g.state == mission::GoalState::kDropped;
    resolved += g.state != mission::GoalState::kPending && g.state != mission::GoalState::kCarried;
  }
  EXPECT_GT(dropped, 0);
  EXPECT_EQ(resolved, requested);
  EXPECT_GT(refused, 0);  // collectors refused what did not fit; the workers kept it
}

}  // namespace
}  // namespace agent
}  // namespace gather
