// roles/role: what a team shares (TeamSetup: who drives each collector, who
// works each segment, deadlines, liveness timeouts, repaired plans kept per
// dead set, the parameters' ranges) and a step's bounded outbox.
#include "gather_agent/roles/role.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "corridor_team.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;

TEST(TeamSetup, NamesWhoDrivesWhatAndWhoWorksWhere) {
  CorridorTeam c;
  const TeamSetup& t = *c.team;
  EXPECT_EQ(t.agents(), 2);
  EXPECT_EQ(t.collector_agent(CollectorId(0)), AgentId(0));
  EXPECT_EQ(t.worker_of_segment(SegmentId(1)), AgentId(1));
  EXPECT_TRUE(t.assignment(AgentId(0)).collector);
  EXPECT_EQ(t.assignment(AgentId(1)).delivers_to, CollectorId(0));
  ASSERT_EQ(t.routes.count(), 1);
  EXPECT_NEAR(t.routes[CollectorId(0)].length(), 29.0, 1e-9);
  // Start poses: free cells next to the OC, one per agent, apart.
  const Point2 a = t.start_pose(AgentId(0)), b = t.start_pose(AgentId(1));
  EXPECT_LT(std::hypot(a.x - 0.55, a.y - 0.25), 1.0);
  EXPECT_GT(std::hypot(a.x - b.x, a.y - b.y), 0.05);
}

TEST(TeamSetup, DeadlinesAndTimeoutsFollowTheRoles) {
  CorridorTeam c;
  const TeamSetup& t = *c.team;
  // The collector's worker: the request reaches it at the meeting point
  // (arc 14.5 m, 14.5 s into the loop), valid for a period (100 s) or until
  // the next one reaches it.
  const double reached = mission::request_reaches_worker(t.routes[CollectorId(0)], 14.5, 1, t.period);
  const double next = mission::request_reaches_worker(t.routes[CollectorId(0)], 14.5, 2, t.period);
  EXPECT_DOUBLE_EQ(t.deadline(AgentId(1), 1), mission::request_deadline(reached, next, t.period));
  EXPECT_EQ(t.deadline(AgentId(0), 1), std::numeric_limits<double>::infinity());  // a collector measures nothing
  // Liveness: a collector is heard once a loop (at least a period), its
  // worker once a loop and a period.
  const double loop = std::max(t.routes[CollectorId(0)].period(), t.period);
  EXPECT_DOUBLE_EQ(t.silent_timeout(t.plan, AgentId(0)), t.params.silent_intervals * loop);
  EXPECT_DOUBLE_EQ(t.silent_timeout(t.plan, AgentId(1)), t.params.silent_intervals * (loop + t.period));
}

TEST(TeamSetup, ARepairedPlanIsKeptPerDeadSetWhateverItsOrder) {
  CorridorTeam c;
  const int16_t one[] = {0}, twice[] = {0, 0};
  const mission::RepairedPlan& a = c.team->repaired(one, 1);
  const mission::RepairedPlan& b = c.team->repaired(twice, 2);
  EXPECT_EQ(&a, &b);
  EXPECT_TRUE(a.dead[AgentId(0)]);
  EXPECT_FALSE(a.plan.file.agents[AgentId(1)].delivers_to.valid());  // the collector's worker now goes to the OC
}

TEST(TeamSetup, ParametersOutOfRangeAndPlansOutOfOrderAreRefused) {
  CorridorTeam c;
  auto refusal = [&](MissionParams p, mission::MissionPlan plan) -> std::string {
    try {
      TeamSetup t(c.world, plan, p);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  MissionParams p = c.params;
  p.silent_intervals = 1.0;
  EXPECT_NE(refusal(p, c.plan).find("--silent-intervals: must be in [1.5, 100]"), std::string::npos);
  p = c.params;
  p.ask_after = 61;
  EXPECT_NE(refusal(p, c.plan).find("ask_after = 61 must be in [0, 60] s"), std::string::npos) << refusal(p, c.plan);
  p = c.params;
  p.protocol.window_margin_m = 200;
  EXPECT_NE(refusal(p, c.plan).find("window_margin_m = 200 must be in [0, 100] m"), std::string::npos);
  p = c.params;
  p.cycles = 0;
  EXPECT_NE(refusal(p, c.plan).find("cycles must be in 1..100000"), std::string::npos);
  mission::MissionPlan swapped = c.plan;  // entry 0 names agent 1: check_plan refuses it for the team
  std::swap(swapped.file.agents[AgentId(0)], swapped.file.agents[AgentId(1)]);
  EXPECT_NE(refusal(c.params, swapped).find("agents must be listed by id"), std::string::npos)
      << refusal(c.params, swapped);
}

TEST(Outbox, RefusesBeyondItsCapacityAndCountsIt) {
  Outbox out(2);
  ASSERT_NE(out.add(Kind::kState, kBroadcast), nullptr);
  Message* m = out.add(Kind::kAck, 3);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->h.kind, Kind::kAck);
  EXPECT_EQ(m->h.dest, 3);
  EXPECT_EQ(out.add(Kind::kData, kOc), nullptr);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(out.refused(), 1);
  out.clear();
  EXPECT_NE(out.add(Kind::kData, kOc), nullptr);
}

}  // namespace
}  // namespace agent
}  // namespace gather
