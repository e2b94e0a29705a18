// mission/worker_policy: a worker's decisions (where and when to hand over,
// which goals fit), on the lingering strip by hand; what a worker on a real
// robot knows (WorkerFacts: its collector's delay, its robot's pace), and
// where a worker of the OC on a robot comes back to, on the corridor by hand.
#include "gather_core/mission/worker_policy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/route_timetable.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/radio/radio_model.hpp"
#include "gather_core/scenario/start_poses.hpp"

namespace gather {
namespace {

using mission::MissionOptions;

// Rendezvous sized by the data (docs/simulator.md, "Hand-over"): on the
// lingering strip one goal needs 10 s of link. Pass A's window (4.14 s) is
// too short; the worker walks on to B, whose window holds for 14.14 s, and
// the link holds over the whole transfer. With instant hand-overs it meets
// the collector at A, the earlier pass.
TEST(HandoverTest, ATransferThatNeedsTenSecondsPicksAPassWhereTheLinkLastsTenSeconds) {
  for (const double bitrate : {1000.0, 0.0}) {
    Scenario s = testing_support::lingering_strip();
    s.radio.bitrate_bps = bitrate;
    const mission::World world(s);
    const mission::MissionPlan mp = testing_support::lingering_plan(s);
    const mission::RouteTimetable route(mp.file.routes[CollectorId(0)], s.team.speed, s.mission.period, world.coverage);
    mission::SharedDistances shared(world);
    mission::WorkerPolicy policy(world, mp, mp.file.agents[AgentId(1)], &route, shared, 4, mission::ProtocolParams{});
    const double range = RadioModel(s.grid, s.radio).free_space_range();
    EXPECT_NEAR(policy.link_window(0).first, 9.5 - range, 0.1);
    EXPECT_NEAR(policy.link_window(0).second, 9.5 + range, 0.1);
    EXPECT_NEAR(policy.link_window(1).first, 28.5 - range, 0.1);
    EXPECT_NEAR(policy.link_window(1).second, 37.5 + 1.0 + range, 0.1);  // out of range on the way home
    EXPECT_EQ(policy.handover_capacity(), bitrate > 0 ? 1u : std::numeric_limits<std::size_t>::max());
    const mission::KnownGoal goal{GoalId(0), s.grid.world_to_cell(Point2{5.05, 0.25}), 200.0};
    policy.learn(&goal, 1);
    const int known[] = {0};
    const auto d = policy.decide(mission::Spot{world.oc_cell}, 0.0, known, 1, 0, false);
    ASSERT_EQ(d.action, mission::WorkerPolicy::Action::kWork);
    ASSERT_EQ(d.k, 1u);
    EXPECT_NEAR(d.at[0], 4.5, 1e-3);
    if (bitrate == 0.0) {
      EXPECT_EQ(d.rendezvous, 0);  // A: the collector passes at 9.5 s, the worker is there at 9.5 s
      EXPECT_NEAR(d.handover, 9.5, 1e-3);
      continue;
    }
    EXPECT_EQ(d.rendezvous, 1);
    EXPECT_NEAR(d.arrive, 4.5 + 24.0, 1e-3);  // from x = 5.05 to 29.05
    EXPECT_NEAR(d.handover, 28.5 + 10.0, 1e-3);
    EXPECT_NEAR(d.link_until, 37.5 + 1.0 + range, 0.1);
    EXPECT_LE(d.handover, d.link_until - 0.5 + 1e-9);
    const Point2 w = policy.rendezvous_point(d.rendezvous);
    const RadioModel radio(s.grid, s.radio);
    for (double t = d.handover - 10.0; t <= d.handover; t += 0.05)
      EXPECT_TRUE(radio.linked(w, route.position(t)) && std::hypot(route.position(t).x - w.x, 0.0) <= range) << t;
  }
}

// The protocol's tuning (ProtocolParams) and the simulator's link checks
// (MissionOptions::link_probe_s) are parameters with ranges.
TEST(HandoverTest, TheProtocolsSamplingStepsAreParametersWithRanges) {
  Scenario s = testing_support::lingering_strip();
  const mission::World world(s);
  const mission::MissionPlan mp = testing_support::lingering_plan(s);
  const mission::RouteTimetable route(mp.file.routes[CollectorId(0)], s.team.speed, s.mission.period, world.coverage);
  mission::SharedDistances shared(world);
  mission::ProtocolParams coarse;
  coarse.link_step_m = 0.7;
  const mission::WorkerPolicy fine_policy(world, mp, mp.file.agents[AgentId(1)], &route, shared, 4,
                                          mission::ProtocolParams{});
  const mission::WorkerPolicy coarse_policy(world, mp, mp.file.agents[AgentId(1)], &route, shared, 4, coarse);
  // A coarser step finds a window no wider, and not the same to the decimetre.
  const auto fine = fine_policy.link_window(0), wide = coarse_policy.link_window(0);
  EXPECT_GE(wide.first, fine.first - 1e-9);
  EXPECT_LE(wide.second, fine.second + 1e-9);
  EXPECT_GT((wide.first - fine.first) + (fine.second - wide.second), 0.05);
  mission::ProtocolParams bad;
  bad.link_step_m = 0.0;
  try {
    mission::WorkerPolicy refused(world, mp, mp.file.agents[AgentId(1)], &route, shared, 4, bad);
    FAIL() << "link_step_m = 0 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("link_step_m = 0 must be in [0.01, 1] m"), std::string::npos) << e.what();
  }
  mission::MissionSimulator sim(world, mp);
  MissionOptions opt;
  opt.cycles = 1;
  opt.link_probe_s = 0.0;
  EXPECT_THROW(sim.run(opt), Error);
}

// WorkerFacts on the corridor (tests/core/corridor.hpp): the collector
// drives OC -> x = 15.05 -> OC in 29 s, three loops a 100 s period; the
// worker's one pass is at x = 15.05 (arc 14.5 m, at 14.5 s on time), linked
// from arc 12.5 to 16.5 m (2.07 m of range, sampled every 0.1 m);
// hand-overs are instant (no bitrate).
struct CorridorPolicy {
  Scenario s = testing_support::corridor();
  mission::World world{s};
  mission::MissionPlan mp = testing_support::corridor_plan(s);
  mission::RouteTimetable route{mp.file.routes[CollectorId(0)], s.team.speed, s.mission.period, world.coverage};
  mission::SharedDistances shared{world};
  mission::WorkerPolicy policy{world, mp, mp.file.agents[AgentId(1)], &route, shared, 4, mission::ProtocolParams{}};
  // One goal at x [m], due at 100 s.
  void goal_at(double x) {
    const mission::KnownGoal g{GoalId(0), s.grid.world_to_cell(Point2{x, 0.25}), 100.0};
    policy.learn(&g, 1);
  }
  mission::WorkerPolicy::Decision decide(const mission::Spot& at, double t, const mission::WorkerFacts& facts) {
    const int known[] = {0};
    return policy.decide(at, t, known, 1, 0, true, 0.0, facts);
  }
};

mission::WorkerFacts facts(double delay, double pace) {
  mission::WorkerFacts f;
  f.collector_delay = delay, f.pace = pace;
  return f;
}

TEST(WorkerFactsTest, TheDefaultsGiveTheDecisionOfAnOnTimeCollectorAndRobot) {
  CorridorPolicy c;
  ASSERT_EQ(c.policy.rendezvous().size(), 1u);
  EXPECT_NEAR(c.policy.link_window(0).first, 12.5, 1e-6);
  EXPECT_NEAR(c.policy.link_window(0).second, 16.5, 1e-6);
  c.goal_at(5.05);
  // From the OC: the goal 4.5 m away at 4.5 s, the pass 10 m on at 14.5 s,
  // when the collector passes; the hand-over at once.
  const int known[] = {0};
  const auto plain = c.policy.decide(mission::Spot{c.world.oc_cell}, 0.0, known, 1, 0, true);
  ASSERT_EQ(plain.action, mission::WorkerPolicy::Action::kWork);
  ASSERT_EQ(plain.k, 1u);
  EXPECT_EQ(plain.rendezvous, 0);
  EXPECT_NEAR(plain.at[0], 4.5, 1e-3);
  EXPECT_NEAR(plain.arrive, 14.5, 1e-3);
  EXPECT_NEAR(plain.pass, 14.5, 1e-9);
  EXPECT_NEAR(plain.handover, 14.5, 1e-3);
  EXPECT_NEAR(plain.link_until, 16.5, 1e-6);
  // Facts{} and {delay 0, pace 1} spelled out: the same decision, to the bit.
  const double at0 = plain.at[0], arrive = plain.arrive, handover = plain.handover, until = plain.link_until,
               pass = plain.pass;
  for (const mission::WorkerFacts& f : {mission::WorkerFacts{}, facts(0.0, 1.0)}) {
    const auto d = c.decide(mission::Spot{c.world.oc_cell}, 0.0, f);
    EXPECT_EQ(d.action, mission::WorkerPolicy::Action::kWork);
    EXPECT_EQ(d.k, 1u);
    EXPECT_EQ(d.rendezvous, 0);
    EXPECT_EQ(d.at[0], at0);
    EXPECT_EQ(d.arrive, arrive);
    EXPECT_EQ(d.handover, handover);
    EXPECT_EQ(d.link_until, until);
    EXPECT_EQ(d.pass, pass);
  }
}

TEST(WorkerFactsTest, ACollectorsDelayShiftsItsPassAndTheMeetingByExactlyTheDelay) {
  CorridorPolicy c;
  // Waiting at the pass with a goal 1 m back: it measures at 1 s, is back at
  // 2 s, and the hand-over starts when the collector's link window opens
  // (arc 12.5 m: 12.5 s on time).
  c.goal_at(14.05);
  const mission::Spot at_pass{c.policy.rendezvous()[0], 0};
  const auto on_time = c.decide(at_pass, 0.0, facts(0.0, 1.0));
  ASSERT_EQ(on_time.action, mission::WorkerPolicy::Action::kWork);
  ASSERT_EQ(on_time.k, 1u);
  EXPECT_NEAR(on_time.at[0], 1.0, 1e-3);
  EXPECT_NEAR(on_time.arrive, 2.0, 1e-3);
  EXPECT_NEAR(on_time.pass, 14.5, 1e-9);
  EXPECT_NEAR(on_time.handover, 12.5, 1e-6);
  EXPECT_NEAR(on_time.link_until, 16.5, 1e-6);
  for (const double delay : {0.5, 3.0, 7.25}) {
    const auto late = c.decide(at_pass, 0.0, facts(delay, 1.0));
    ASSERT_EQ(late.action, mission::WorkerPolicy::Action::kWork) << delay;
    ASSERT_EQ(late.k, 1u) << delay;
    EXPECT_EQ(late.rendezvous, on_time.rendezvous) << delay;
    EXPECT_NEAR(late.pass - on_time.pass, delay, 1e-9) << delay;
    EXPECT_NEAR(late.handover - on_time.handover, delay, 1e-9) << delay;
    EXPECT_NEAR(late.link_until - on_time.link_until, delay, 1e-9) << delay;
    // Its own way is not the collector's business.
    EXPECT_EQ(late.at[0], on_time.at[0]) << delay;
    EXPECT_EQ(late.arrive, on_time.arrive) << delay;
  }
  // From the OC, arriving with the collector (14.5 s): 3 s late, the pass
  // is at 17.5 s and the hand-over starts when its window opens, 15.5 s.
  c.goal_at(5.05);
  const auto from_oc = c.decide(mission::Spot{c.world.oc_cell}, 0.0, facts(3.0, 1.0));
  EXPECT_NEAR(from_oc.pass, 17.5, 1e-9);
  EXPECT_NEAR(from_oc.handover, 15.5, 1e-6);
  EXPECT_NEAR(from_oc.link_until, 19.5, 1e-6);
}

TEST(WorkerFactsTest, ASlowerPaceMakesEveryTravelTimeLongerByOneOverThePace) {
  CorridorPolicy c;
  c.goal_at(14.05);
  const mission::Spot at_pass{c.policy.rendezvous()[0], 0};
  const double t = 10.0;
  const auto base = c.decide(at_pass, t, facts(0.0, 1.0));
  const double to_goal = base.at[0] - t, to_pass = base.arrive - t;
  EXPECT_NEAR(to_goal, 1.0, 1e-3);
  EXPECT_NEAR(to_pass, 2.0, 1e-3);
  for (const double pace : {0.5, 0.8, 2.0}) {
    const auto d = c.decide(at_pass, t, facts(0.0, pace));
    ASSERT_EQ(d.action, mission::WorkerPolicy::Action::kWork) << pace;
    ASSERT_EQ(d.k, 1u) << pace;
    EXPECT_NEAR(d.at[0] - t, to_goal / pace, 1e-9) << pace;
    EXPECT_NEAR(d.arrive - t, to_pass / pace, 1e-9) << pace;
    EXPECT_NEAR(d.pass, 14.5, 1e-9) << pace;  // still in time for the same pass
  }
  // From the OC at half pace: the goal at 9 s, the pass reached at 29 s,
  // after the collector's first loop went by: it meets the second (43.5 s).
  c.goal_at(5.05);
  const auto slow = c.decide(mission::Spot{c.world.oc_cell}, 0.0, facts(0.0, 0.5));
  ASSERT_EQ(slow.action, mission::WorkerPolicy::Action::kWork);
  ASSERT_EQ(slow.k, 1u);
  EXPECT_NEAR(slow.at[0], 9.0, 2e-3);
  EXPECT_NEAR(slow.arrive, 29.0, 2e-3);
  EXPECT_NEAR(slow.pass, 43.5, 1e-9);
  EXPECT_NEAR(slow.handover, 41.5, 1e-6);
  // A goal it would reach only after its deadline at that pace is left out:
  // 4.5 m at 0.05 m/s is 90 s, past a deadline of 60 s.
  const mission::KnownGoal due{GoalId(0), c.s.grid.world_to_cell(Point2{5.05, 0.25}), 60.0};
  c.policy.learn(&due, 1);
  const int known[] = {0};
  EXPECT_EQ(c.policy.decide(mission::Spot{c.world.oc_cell}, 0.0, known, 1, 0, true, 0.0, facts(0.0, 0.05)).k, 0u);
  EXPECT_EQ(c.policy.decide(mission::Spot{c.world.oc_cell}, 0.0, known, 1, 0, true, 0.0, facts(0.0, 1.0)).k, 1u);
}

TEST(WorkerFactsTest, AWorkerOfTheOcComesBackIntoTheCoverageAtItsPace) {
  const Scenario s = testing_support::corridor();
  const mission::World world(s);
  const mission::MissionPlan mp = testing_support::corridor_plan_without_collector(s);
  mission::SharedDistances shared(world);
  mission::WorkerPolicy policy(world, mp, mp.file.agents[AgentId(0)], nullptr, shared, 4, mission::ProtocolParams{});
  const Cell away{2, 100};  // x = 10.05 m, 7.5 m from the coverage
  const double way = policy.way_back(away).second;
  EXPECT_NEAR(way, 7.5, 0.15);
  const double t = 20.0;
  const auto plain = policy.decide(mission::Spot{away}, t, nullptr, 0, 0, true);
  ASSERT_EQ(plain.action, mission::WorkerPolicy::Action::kBackToCoverage);
  EXPECT_EQ(plain.arrive, t + way);
  const auto slow = policy.decide(mission::Spot{away}, t, nullptr, 0, 0, true, 0.0, facts(0.0, 0.5));
  ASSERT_EQ(slow.action, mission::WorkerPolicy::Action::kBackToCoverage);
  EXPECT_NEAR(slow.arrive - t, way / 0.5, 1e-9);
  EXPECT_EQ(slow.landing, plain.landing);
  // A collector's delay means nothing to a worker of the OC.
  const auto delayed = policy.decide(mission::Spot{away}, t, nullptr, 0, 0, true, 0.0, facts(12.0, 1.0));
  EXPECT_EQ(delayed.arrive, plain.arrive);
}

// One worker of the OC owning an open floor (testing_support::one_agent_floor):
// its policy with the ideal protocol and with the robot protocol.
struct FloorWorker {
  Scenario s = testing_support::one_agent_floor();
  mission::World world{s};
  mission::MissionPlan mp = testing_support::corridor_plan_without_collector(s);
  mission::SharedDistances shared{world};
  mission::WorkerPolicy ideal{world, mp, mp.file.agents[AgentId(0)], nullptr, shared, 4, mission::ProtocolParams{}};
  mission::WorkerPolicy robots{
      world, mp, mp.file.agents[AgentId(0)], nullptr, shared, 4, mission::robot_protocol(mission::ProtocolParams{})};
};

TEST(WorkerFactsTest, OnRobotsAWorkerOfTheOcComesBackToItsHomeAndStaysNearIt) {
  FloorWorker f;
  const Scenario& s = f.s;
  const mission::World& world = f.world;
  mission::WorkerPolicy& ideal = f.ideal;
  mission::WorkerPolicy& policy = f.robots;
  EXPECT_FALSE(ideal.back_to_home());
  ASSERT_TRUE(policy.back_to_home());
  ASSERT_TRUE(world.covered(policy.home()));
  EXPECT_NE(policy.home(), ideal.home());  // the plain home is a corner of the coverage, with no room
  // The way back from x = 9 m: into the coverage where the ideal base
  // comes back (a border cell), then on to the home.
  const Cell away{30, 90};
  const auto border = ideal.way_back(away);
  const auto back = policy.way_back(away);
  EXPECT_EQ(back.first, policy.home());
  const Point2 h = s.grid.cell_center(policy.home());
  const Point2 b = s.grid.cell_center(border.first);
  EXPECT_NEAR(back.second, border.second + std::hypot(b.x - h.x, b.y - h.y), 0.15);
  const double t = 20.0;
  const auto d = policy.decide(mission::Spot{away}, t, nullptr, 0, 0, true);
  ASSERT_EQ(d.action, mission::WorkerPolicy::Action::kBackToCoverage);
  EXPECT_EQ(d.landing, policy.home());
  EXPECT_NEAR(d.arrive, t + back.second, 1e-9);
  // Covered cells 0.5 m and 1.5 m from the home.
  auto covered_at = [&](double dist) {
    for (std::size_t i = 0; i < s.grid.size(); ++i) {
      const Cell c = s.grid.cell(i);
      const Point2 p = s.grid.cell_center(c);
      if (world.covered(c) && std::abs(std::hypot(p.x - h.x, p.y - h.y) - dist) < 0.05) return c;
    }
    return Cell{-1, -1};
  };
  const Cell near = covered_at(0.5), far_off = covered_at(1.5);
  ASSERT_GE(near.row, 0);
  ASSERT_GE(far_off.row, 0);
  // Its robot stopped within the place tolerance (1 m) of the home, back
  // from a trip: it waits there (it does not send its robot home again).
  mission::Spot landed{near};
  landed.landing = true;
  EXPECT_EQ(policy.decide(landed, t, nullptr, 0, 0, true).action, mission::WorkerPolicy::Action::kWait);
  // Not back from a trip, or further than the tolerance: home.
  EXPECT_EQ(policy.decide(mission::Spot{near}, t, nullptr, 0, 0, true).action,
            mission::WorkerPolicy::Action::kGoToMeeting);
  mission::Spot beyond{far_off};
  beyond.landing = true;
  EXPECT_EQ(policy.decide(beyond, t, nullptr, 0, 0, true).action, mission::WorkerPolicy::Action::kGoToMeeting);
  // Ideal bases (no room asked) wait on the home cell only.
  EXPECT_EQ(ideal.decide(landed, t, nullptr, 0, 0, true).action, mission::WorkerPolicy::Action::kGoToMeeting);
}

// On robots a worker of the OC plans at the team speed whatever its robot's
// pace (a goal its robot may still reach in time is worth the drive; it
// tells the OC when it will be back at its pace); with the ideal protocol
// it plans at its robot's pace, as a worker of a collector does.
TEST(WorkerFactsTest, OnRobotsAWorkerOfTheOcPlansAtTheTeamSpeed) {
  FloorWorker f;
  const Scenario& s = f.s;
  mission::WorkerPolicy& ideal = f.ideal;
  mission::WorkerPolicy& robots = f.robots;
  EXPECT_FALSE(ideal.tours_at_team_speed());
  ASSERT_TRUE(robots.tours_at_team_speed());
  // A goal about 8 m from the home (x = 9.05 m), due in 12 s: in time at
  // the team speed (1 m/s here), not at half of it.
  const Point2 goal{9.05, 3.05};
  const mission::KnownGoal due{GoalId(0), s.grid.world_to_cell(goal), 12.0};
  ideal.learn(&due, 1);
  robots.learn(&due, 1);
  const int known[] = {0};
  const double t = 0.0;
  const auto on_plan = robots.decide(mission::Spot{robots.home()}, t, known, 1, 0, true, 0.0, facts(0.0, 1.0));
  const auto slow = robots.decide(mission::Spot{robots.home()}, t, known, 1, 0, true, 0.0, facts(0.0, 0.5));
  ASSERT_EQ(slow.action, mission::WorkerPolicy::Action::kWork);
  ASSERT_EQ(slow.k, 1u);
  EXPECT_EQ(slow.pace, 1.0);
  EXPECT_EQ(slow.at[0], on_plan.at[0]);
  EXPECT_LT(slow.at[0], 12.0);
  EXPECT_GT(2.0 * slow.at[0], 12.0);
  const auto slow_ideal = ideal.decide(mission::Spot{ideal.home()}, t, known, 1, 0, true, 0.0, facts(0.0, 0.5));
  EXPECT_EQ(slow_ideal.pace, 0.5);
  EXPECT_EQ(slow_ideal.k, 0u);  // at half pace it would be there after 12 s
}

// Where the team starts (mission::team_start_poses). A 2.5 m x 5 m room,
// the OC in its middle, a corridor 1.2 m wide east out of it: agents 0-3
// are workers of the OC owning parts of the corridor, agent 4 a collector.
// The ideal protocol packs the team next to the OC, as before; on robots
// each worker of the OC starts parked at its home, the collector by the OC,
// every robot at least kStartSpacing from the others.
TEST(TeamStartTest, OnRobotsTheWorkersOfTheOcStartAtTheirHomes) {
  const Scenario s = testing_support::room_with_corridor(5);
  const mission::World world(s);
  mission::MissionPlan mp;
  mp.labels = LabelImage(s.grid.frame(), 0);
  for (int k = 0; k < 4; ++k)  // segment k + 1: x 4.5-5, 5.5-6, ... down the corridor
    for (int r = 19; r <= 30; ++r)
      for (int c = 45 + 10 * k; c < 50 + 10 * k; ++c) mp.labels.at(Cell{r, c}) = k + 1;
  mp.file.method = "hand";
  mp.file.workers = 4, mp.file.cycle_period_s = 100.0;
  for (int k = 0; k < 4; ++k)
    mp.file.agents.push_back(plan::AgentAssignment{AgentId(k), false, SegmentId(k + 1), CollectorId()});
  mp.file.agents.push_back(plan::AgentAssignment{AgentId(4), true, SegmentId(), CollectorId(0)});

  const std::vector<Point2> packed = start_poses(s.grid, s.oc, 5);
  const std::vector<Point2> ideal = mission::team_start_poses(world, mp, {});
  ASSERT_EQ(ideal.size(), packed.size());
  for (std::size_t k = 0; k < ideal.size(); ++k)
    EXPECT_TRUE(ideal[k].x == packed[k].x && ideal[k].y == packed[k].y) << k;

  const mission::ProtocolParams robots = mission::robot_protocol(mission::ProtocolParams{});
  const std::vector<Cell> homes = mission::oc_worker_homes(world, mp, robots.home_clearance_m);
  ASSERT_EQ(homes.size(), 5u);
  EXPECT_EQ(homes[4], (Cell{-1, -1}));  // the collector has none
  const std::vector<Point2> starts = mission::team_start_poses(world, mp, homes);
  ASSERT_EQ(starts.size(), 5u);
  for (std::size_t k = 0; k < 4; ++k) {
    ASSERT_GE(homes[k].row, 0) << k;
    EXPECT_EQ(s.grid.world_to_cell(starts[k]), homes[k]) << k;
  }
  EXPECT_LT(std::hypot(starts[4].x - s.oc.x, starts[4].y - s.oc.y), 1.5);  // by the OC
  for (std::size_t k = 0; k < starts.size(); ++k) {
    EXPECT_TRUE(world.reaches(s.grid.world_to_cell(starts[k]))) << k;
    for (std::size_t j = 0; j < k; ++j)
      EXPECT_GE(std::hypot(starts[k].x - starts[j].x, starts[k].y - starts[j].y), kStartSpacing - 1e-9)
          << k << " " << j;
  }
  // The policy of each worker finds the same home.
  mission::SharedDistances shared(world, false);
  for (std::size_t k = 0; k < 4; ++k) {
    mission::WorkerPolicy policy(world, mp, mp.file.agents[AgentId(static_cast<int>(k))], nullptr, shared, 4, robots);
    EXPECT_EQ(policy.home(), homes[k]) << k;
  }
}

}  // namespace
}  // namespace gather
