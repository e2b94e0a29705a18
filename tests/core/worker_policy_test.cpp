// mission/worker_policy: a worker's decisions (where and when to hand over,
// which goals fit), on the lingering strip by hand.
#include "gather_core/mission/worker_policy.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/route_timetable.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/radio/radio_model.hpp"

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

}  // namespace
}  // namespace gather
