// roles/oc_role: the OC delivers once, counts duplicates, acks all, expires
// skipped requests and goals in no segment, takes the later deadline its
// workers applied, expires what was measured after it, resolves goals its
// workers' robots could not reach as unreachable, and delivers a goal one
// worker gave up that another measured.
#include "gather_agent/roles/oc_role.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "corridor_team.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/mission/simulator.hpp"

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
  for (int i = 0; i < 2; ++i) d.data.items[i].picked_up_by = 0, d.data.items[i].picked_up_at = 5.0;
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
  // Who may hand an item in (its sender is sure: per-link keys): worker 1
  // with a measurement collector 0 took, and collector 0 with one no
  // collector took, are refused (and acked: their sender lets go).
  Message claim = message(Kind::kData, 1, kOc, 3, Point2{1.0, 0.25});
  claim.data.count = 1, claim.data.items[0] = measured(1, 1, 151.0);
  claim.data.items[0].picked_up_by = 0, claim.data.items[0].picked_up_at = 151.5;
  oc.step(153.0, {claim});
  Message untaken = message(Kind::kData, 0, kOc, 3, Point2{1.0, 0.25});
  untaken.data.count = 1, untaken.data.items[0] = measured(1, 1, 151.0);
  oc.step(154.0, {untaken});
  EXPECT_FALSE(role.resolved(GoalId(1)));
  EXPECT_EQ(role.invalid_items(), 6);
  EXPECT_EQ(oc.sent(Kind::kAck)->ack.count, 1u);
  // The same measurement from its worker, no collector between: taken.
  Message own = message(Kind::kData, 1, kOc, 4, Point2{1.0, 0.25});
  own.data.count = 1, own.data.items[0] = measured(1, 1, 151.0);
  oc.step(155.0, {own});
  EXPECT_TRUE(role.resolved(GoalId(1)));
  EXPECT_EQ(role.invalid_items(), 6);
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
// The deadline a worker applied travels with its items: the OC takes it
// when it is later than the timetable's (the collector handed the request
// over late), never an earlier one; a measurement after the deadline it
// adopted is recorded as an expiry (late_items()); an item a robot could
// not reach resolves its goal as unreachable. The ledger then accounts.
TEST(OcRole, AdoptsALaterDeadlineExpiresLateMeasurementsAndResolvesUnreachableGoals) {
  CorridorTeam c(1, {{0, {5.05, 0.25}}, {0, {9.05, 0.25}}, {0, {12.05, 0.25}}, {0, {7.05, 0.25}}});
  Stepper oc{make_oc(*c.team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  ASSERT_EQ(role.requested(), 4u);
  for (const mission::GoalRecord& g : role.goals()) ASSERT_DOUBLE_EQ(g.deadline, 100.0);  // the timetable's
  // From its collector (picked up at the meeting), at 110 s:
  Message d = message(Kind::kData, 0, kOc, 0, Point2{1.0, 0.25});
  d.data.count = 5;
  // goal 0: measured at 95 s by a worker that applied 90 s (earlier than
  // the timetable's: not taken), in time for 100 s: delivered.
  d.data.items[0] = measured(0, 1, 95.0);
  d.data.items[0].deadline = 90.0;
  // goal 1: measured at 103 s, the worker's deadline 104 s (its collector
  // 4 s late): taken, and in time.
  d.data.items[1] = measured(1, 1, 103.0);
  d.data.items[1].deadline = 104.0;
  // goal 2: measured at 105 s, after the 104 s its worker applied: expired.
  d.data.items[2] = measured(2, 1, 105.0);
  d.data.items[2].deadline = 104.0;
  for (int i = 0; i < 3; ++i) d.data.items[i].picked_up_by = 0, d.data.items[i].picked_up_at = 106.0;
  // goal 3: its robot gave it up at 7 s.
  DataItem gone;
  gone.key = 3, gone.kind = ItemKind::kUnreachable, gone.by = 1, gone.at = 7.0, gone.deadline = 100.0;
  d.data.items[3] = gone;
  // A deadline of +inf (a worker of the OC's) is no deadline to take:
  // goal 0 again, a duplicate.
  d.data.items[4] = measured(0, 1, 95.0);
  d.data.items[4].deadline = std::numeric_limits<double>::infinity();
  d.data.items[4].picked_up_by = 0, d.data.items[4].picked_up_at = 106.0;
  oc.step(110.0, {d});
  ASSERT_NE(oc.sent(Kind::kAck), nullptr);
  EXPECT_EQ(oc.sent(Kind::kAck)->ack.count, 5u);
  EXPECT_EQ(role.invalid_items(), 0);
  EXPECT_EQ(role.duplicate_items(), 1);
  const std::vector<mission::GoalRecord>& g = role.goals();
  EXPECT_EQ(g[0].state, mission::GoalState::kDelivered);
  EXPECT_DOUBLE_EQ(g[0].deadline, 100.0);  // 90 s not taken; +inf neither
  EXPECT_EQ(g[1].state, mission::GoalState::kDelivered);
  EXPECT_DOUBLE_EQ(g[1].deadline, 104.0);  // taken
  EXPECT_DOUBLE_EQ(g[1].measured_at, 103.0);
  EXPECT_EQ(g[2].state, mission::GoalState::kExpired);
  EXPECT_DOUBLE_EQ(g[2].deadline, 104.0);
  EXPECT_DOUBLE_EQ(g[2].expired_at, 104.0);  // at its deadline, not when measured
  EXPECT_LT(g[2].measured_at, 0.0);          // its data is not a measurement
  EXPECT_LT(g[2].delivered_at, 0.0);
  EXPECT_EQ(role.late_items(), 1);
  EXPECT_EQ(g[3].state, mission::GoalState::kUnreachable);
  EXPECT_DOUBLE_EQ(g[3].unreachable_at, 7.0);
  EXPECT_LT(g[3].expired_at, 0.0);
  EXPECT_EQ(role.delivered_by(AgentId(0)), 2);
  EXPECT_TRUE(role.done());
  // The ledger accounts: 2 delivered, 1 expired, 1 unreachable.
  const std::vector<mission::CycleStats> cycles = mission::account(g, 1, c.team->period);
  ASSERT_EQ(cycles.size(), 1u);
  EXPECT_EQ(cycles[0].delivered, 2);
  EXPECT_EQ(cycles[0].expired, 1);
  EXPECT_EQ(cycles[0].unreachable, 1);
}

TEST(OcRole, AnUnreachableItemAfterItsGoalWasResolvedIsADuplicate) {
  CorridorTeam c(1, {{0, {5.05, 0.25}}});
  Stepper oc{make_oc(*c.team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  DataItem gone;
  gone.key = 0, gone.kind = ItemKind::kUnreachable, gone.by = 1, gone.at = 3.0, gone.deadline = 100.0;
  Message d = message(Kind::kData, 0, kOc, 0, Point2{1.0, 0.25});
  d.data.count = 1, d.data.items[0] = gone;
  oc.step(5.0, {d});
  ASSERT_EQ(role.goals()[0].state, mission::GoalState::kUnreachable);
  // Then data for it (a worker gone wrong): the goal stays unreachable.
  d.h.seq = 1, d.data.items[0] = measured(0, 1, 4.0);
  d.data.items[0].picked_up_by = 0, d.data.items[0].picked_up_at = 4.5;
  oc.step(6.0, {d});
  EXPECT_EQ(role.goals()[0].state, mission::GoalState::kUnreachable);
  EXPECT_DOUBLE_EQ(role.goals()[0].unreachable_at, 3.0);
  EXPECT_LT(role.goals()[0].delivered_at, 0.0);
  EXPECT_EQ(role.duplicate_items(), 1);
  // An unreachable notice dated before its request is no news of it.
  CorridorTeam c2(2, {{0, {5.05, 0.25}}, {1, {7.05, 0.25}}});
  Stepper oc2{make_oc(*c2.team)};
  auto& role2 = static_cast<OcRole&>(*oc2.unit.role);
  oc2.step(0.0);
  oc2.step(100.0);  // request 1: goal 1
  gone.key = 1, gone.at = 50.0;
  d.data.items[0] = gone;
  oc2.step(101.0, {d});
  EXPECT_FALSE(role2.resolved(GoalId(1)));
  EXPECT_EQ(role2.invalid_items(), 1);
}

TEST(OcRole, ARevokedWorkerIsDeclaredAtOnceItsMessagesDroppedAndWhatItHeldThenRefused) {
  CorridorTeam c(2, {{0, {5.05, 0.25}}, {0, {9.05, 0.25}}, {1, {7.05, 0.25}}});
  c.team->params.revoke = {{1, 10.0}};
  Stepper oc{make_oc(*c.team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  oc.step(10.0);
  EXPECT_DOUBLE_EQ(role.revoked_at(AgentId(1)), 10.0);
  EXPECT_DOUBLE_EQ(role.declared_dead_at(AgentId(1)), 10.0);  // at once
  const Message* news = oc.sent(Kind::kRequest);
  ASSERT_NE(news, nullptr);
  ASSERT_EQ(news->request.dead_count, 1u);
  EXPECT_EQ(news->request.dead[0], 1);
  EXPECT_EQ(news->request.dead_revoked, 1u);
  EXPECT_EQ(role.goals()[0].state, mission::GoalState::kLostWithAgent);
  EXPECT_EQ(role.goals()[1].state, mission::GoalState::kLostWithAgent);
  // Its collector (agent 0) hands in two of its measurements: one taken
  // from it before the revocation (delivered, recovered), one after (refused).
  Message d = message(Kind::kData, 0, kOc, 0, Point2{1.0, 0.25});
  d.data.count = 3, d.data.items[0] = measured(0, 1, 4.5), d.data.items[1] = measured(1, 1, 4.6);
  d.data.items[0].picked_up_by = 0, d.data.items[0].picked_up_at = 9.0;
  d.data.items[1].picked_up_by = 0, d.data.items[1].picked_up_at = 11.0;
  d.data.items[2] = measured(1, 1, 4.6);  // the same, claimed as its own by the collector: not its to hand in
  oc.step(12.0, {d});
  EXPECT_EQ(role.goals()[0].state, mission::GoalState::kDelivered);
  EXPECT_EQ(role.goals()[1].state, mission::GoalState::kLostWithAgent);
  EXPECT_EQ(role.discarded_of(AgentId(1)), 1);
  EXPECT_TRUE(role.discarded(GoalId(1)));
  EXPECT_FALSE(role.discarded(GoalId(0)));
  EXPECT_EQ(role.invalid_items(), 1);
  ASSERT_NE(oc.sent(Kind::kAck), nullptr);
  EXPECT_EQ(oc.sent(Kind::kAck)->ack.count, 3u);  // acked, all: the collector lets go
  // The revoked worker hands in its own: dropped before the role, counted, not acked.
  Message own = message(Kind::kData, 1, kOc, 0, Point2{1.0, 0.25});
  own.data.count = 1, own.data.items[0] = measured(1, 1, 4.6);
  oc.step(13.0, {own});
  EXPECT_EQ(oc.sent(Kind::kAck), nullptr);
  EXPECT_EQ(role.refused_revoked(0), 1);
  EXPECT_EQ(role.goals()[1].state, mission::GoalState::kLostWithAgent);
}

TEST(OcRole, AnAgentDeclaredDeadBeforeIsRevokedTooAndTheNewsBroadcast) {
  CorridorTeam c(2, {{0, {5.05, 0.25}}, {0, {9.05, 0.25}}, {1, {7.05, 0.25}}});
  c.team->params.revoke = {{1, 5000.0}};
  Stepper oc{make_oc(*c.team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  double t = 0.0;
  while (role.declared_dead_at(AgentId(1)) < 0 && t < 4000.0) oc.step(t += 10.0);  // silent: declared
  ASSERT_GE(role.declared_dead_at(AgentId(1)), 0.0);
  EXPECT_EQ(role.revoked_mask(), 0u);
  oc.step(5000.0);
  EXPECT_DOUBLE_EQ(role.revoked_at(AgentId(1)), 5000.0);
  std::size_t i = 0;
  while (role.dead()[i] != 1) ++i;
  EXPECT_EQ(role.revoked_mask(), 1u << i);
  const Message* news = oc.sent(Kind::kRequest);
  ASSERT_NE(news, nullptr);
  EXPECT_EQ(news->request.dead_revoked, 1u << i);
}

TEST(Conservation, EachMeasuredGoalIsDeliveredCarriedOrRefusedAndNothingElseIs) {
  CorridorTeam c(2, {{0, {5.05, 0.25}}, {0, {9.05, 0.25}}, {1, {7.05, 0.25}}});
  Stepper oc{make_oc(*c.team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  Message d = message(Kind::kData, 0, kOc, 0, Point2{1.0, 0.25});
  d.data.count = 1, d.data.items[0] = measured(0, 1, 4.5);
  d.data.items[0].picked_up_by = 0, d.data.items[0].picked_up_at = 5.0;
  oc.step(6.0, {d});  // goal 0 delivered
  std::vector<uint8_t> m(role.goals().size(), 0);
  std::vector<int32_t> custody;
  m[0] = 1;
  EXPECT_NO_THROW(check_conservation(role, m, custody, 6.0));
  m[1] = 1;  // goal 1 measured, held by nobody: lost
  EXPECT_THROW(check_conservation(role, m, custody, 6.0), RuntimeError);
  custody = {1};  // carried
  EXPECT_NO_THROW(check_conservation(role, m, custody, 6.0));
  custody = {1, 2};  // goal 2 carried, but nobody measured it
  EXPECT_THROW(check_conservation(role, m, custody, 6.0), RuntimeError);
  custody = {1, 0};  // a copy of delivered goal 0 still held (its ack on the way): the same measurement
  EXPECT_NO_THROW(check_conservation(role, m, custody, 6.0));
  m[0] = 2;  // measured by two workers: one copy delivered is enough
  EXPECT_NO_THROW(check_conservation(role, m, custody, 6.0));
  m[0] = 0;  // delivered, never measured
  EXPECT_THROW(check_conservation(role, m, custody, 6.0), RuntimeError);
}

// A goal its owner gave up (expired) that another worker measured after
// all (it took the segment over while the OC and the owner disagreed on
// who is dead): the data is real, delivered; acked and dropped, it would
// be lost (gather run's conservation check stopped the cave, seed 2). Here
// the owner's own later measurement of it, and a claim of it by the
// corridor's collector, which no plan gives a cell: neither is news.
// (The takeover itself: Revocation.AClaimOfAGoalNoPlanGaveTheClaimantIsRefused.)
TEST(OcRole, AMeasurementOfAGoalAnotherWorkerGaveUpIsDelivered) {
  CorridorTeam c(1, {{0, {5.05, 0.25}}, {0, {6.05, 0.25}}});
  Stepper oc{make_oc(*c.team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  DataItem gave_up;
  gave_up.key = 0, gave_up.kind = ItemKind::kExpired, gave_up.by = 1, gave_up.at = 3.0, gave_up.deadline = 3.0;
  Message d = message(Kind::kData, 1, kOc, 0, Point2{1.0, 0.25});
  d.data.count = 1, d.data.items[0] = gave_up;
  oc.step(5.0, {d});
  ASSERT_EQ(role.goals()[0].state, mission::GoalState::kExpired);
  // Agent 0 (the collector) claims to have measured it: refused.
  Message m = message(Kind::kData, 0, kOc, 0, Point2{1.0, 0.25});
  m.data.count = 1, m.data.items[0] = measured(0, 0, 4.0);
  oc.step(6.0, {m});
  EXPECT_EQ(role.goals()[0].state, mission::GoalState::kExpired);
  EXPECT_EQ(role.invalid_items(), 1);
  EXPECT_EQ(role.overridden(), 0);
  ASSERT_NE(oc.sent(Kind::kAck), nullptr);  // acked all the same: its sender lets go
  // Its owner contradicting itself (expired, then data) is not news: goal 1.
  gave_up.key = 1;
  d.h.seq = 1, d.data.items[0] = gave_up;
  oc.step(8.0, {d});
  d.h.seq = 2, d.data.items[0] = measured(1, 1, 4.5);
  oc.step(9.0, {d});
  EXPECT_EQ(role.goals()[1].state, mission::GoalState::kExpired);
  EXPECT_EQ(role.duplicate_items(), 1);
}
}  // namespace
}  // namespace agent
}  // namespace gather
