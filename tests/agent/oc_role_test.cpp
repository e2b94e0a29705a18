// roles/oc_role: the OC delivers once, counts duplicates, acks all, expires
// skipped requests and goals in no segment.
#include "gather_agent/roles/oc_role.hpp"

#include <gtest/gtest.h>

#include "corridor_team.hpp"
#include "gather_agent/runner/team_runner.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;
using agent_testing::measured;
using agent_testing::message;
using agent_testing::request;
using agent_testing::Stepper;

TEST(OcRole, DeliversOnceCountsDuplicatesAcksAllAndExpiresSkippedRequests) {
  CorridorTeam c(2, {{0, {5.05, 0.25}}, {0, {9.05, 0.25}}, {1, {7.05, 0.25}}});
  Stepper oc{make_oc(*c.team)};
  oc.step(0.0);
  const Message* req = oc.sent(Kind::kRequest);
  ASSERT_NE(req, nullptr);
  EXPECT_EQ(req->h.dest, kBroadcast);
  EXPECT_EQ(req->request.count, 2u);
  Message d = message(Kind::kData, 0, kOc, 0, Point2{1.0, 0.25});
  d.data.count = 2, d.data.items[0] = measured(0, 1, 4.5), d.data.items[1] = measured(0, 1, 4.5);
  d.data.items[0].picked_up_by = 0, d.data.items[0].picked_up_at = 5.0;
  oc.step(27.0, {d});
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  EXPECT_TRUE(role.resolved(GoalId(0)));
  EXPECT_EQ(role.duplicate_items(), 1);
  ASSERT_NE(oc.sent(Kind::kAck), nullptr);
  EXPECT_EQ(oc.sent(Kind::kAck)->ack.count, 2u);
  EXPECT_EQ(role.goals()[0].delivered_at, 27.0);
  EXPECT_EQ(role.goals()[0].delivered_by, AgentId(0));
  // Request 1 is issued at 100 s; worker 1 reports it never reached it.
  oc.step(100.0);
  Message s = message(Kind::kData, 0, kOc, 1, Point2{1.0, 0.25});
  DataItem skip;
  skip.key = skipped_key(1, 1), skip.kind = ItemKind::kSkipped, skip.by = 1, skip.at = 143.5;
  DataItem bogus = measured(99, 1, 1.0);  // no such goal
  s.data.count = 2, s.data.items[0] = skip, s.data.items[1] = bogus;
  oc.step(150.0, {s});
  EXPECT_TRUE(role.resolved(GoalId(2)));
  EXPECT_EQ(role.goals()[2].state, mission::GoalState::kExpired);
  EXPECT_EQ(role.goals()[2].expired_at, 143.5);
  EXPECT_EQ(role.invalid_items(), 1);
  EXPECT_EQ(oc.sent(Kind::kAck)->ack.count, 2u);  // the bogus item is acked too: its sender lets go
  // Items naming agents outside the team (a worker, or the collector that
  // took it) place nothing: goal 1 stays open.
  Message named = message(Kind::kData, 1, kOc, 2, Point2{1.0, 0.25});
  named.data.count = 3;
  named.data.items[0] = measured(1, 7, 151.0);   // no agent 7
  named.data.items[1] = measured(1, -1, 151.0);  // no worker at all
  named.data.items[2] = measured(1, 1, 151.0);
  named.data.items[2].picked_up_by = 9, named.data.items[2].picked_up_at = 151.5;  // no collector 9
  oc.step(152.0, {named});
  EXPECT_FALSE(role.resolved(GoalId(1)));
  EXPECT_EQ(role.invalid_items(), 4);
  EXPECT_EQ(oc.sent(Kind::kAck)->ack.count, 3u);
}

TEST(OcRole, AGoalInNoSegmentExpiresWhenTheNextRequestIsDue) {
  CorridorTeam c(2, {{0, {5.05, 0.25}}, {0, {19.55, 0.25}}});
  // The last half metre of the corridor in no worker's segment.
  for (int r = 0; r < 5; ++r)
    for (int q = 195; q < 200; ++q) c.plan.labels[static_cast<std::size_t>(r) * 200 + static_cast<std::size_t>(q)] = 0;
  c.team = std::make_unique<TeamSetup>(c.world, c.plan, c.params);
  const RunOutcome out = TeamRunner(*c.team, RunOptions{}).run();
  ASSERT_TRUE(out.completed) << out.failure;
  EXPECT_FALSE(out.result.goals[1].worker.valid());
  EXPECT_EQ(out.result.goals[1].state, mission::GoalState::kExpired);
  EXPECT_DOUBLE_EQ(out.result.goals[1].expired_at, 100.0);
}
}  // namespace
}  // namespace agent
}  // namespace gather
