// The agent runtime without a transport: custody, the range gate, the
// inbox order, each role driven by hand on the corridor (hand-over at the
// pass, delivery, expiry, a duplicate counted once, a lost ack resent, an
// out-of-range message gated), the whole team on the corridor against
// hand-computed times, and the team on maps/office against the analytic
// simulator (the equivalence guard), with lossy radio, deterministically.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

#include "../core/corridor.hpp"
#include "gather_agent/roles/collector_role.hpp"
#include "gather_agent/roles/oc_role.hpp"
#include "gather_agent/roles/worker_role.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/radio/radio_model.hpp"
#include "office_team.hpp"

namespace gather {
namespace agent {
namespace {

using testing_support::corridor;
using testing_support::corridor_plan;

DataItem measured(int32_t goal, int16_t by, double at) {
  DataItem d;
  d.key = goal, d.kind = ItemKind::kMeasured, d.by = by, d.at = at;
  return d;
}

TEST(Custody, KeepsOneCopyPerKeyRefusesWhenFullAndForgetsWhatIsAcked) {
  Custody c(2, 1);
  EXPECT_EQ(c.put(measured(5, 1, 1.0)), Custody::Put::kStored);
  EXPECT_EQ(c.put(measured(5, 1, 1.0)), Custody::Put::kDuplicate);
  EXPECT_EQ(c.put(measured(6, 1, 2.0)), Custody::Put::kStored);
  EXPECT_EQ(c.put(measured(7, 1, 3.0)), Custody::Put::kFull);  // data full; the sender keeps it
  DataItem n;
  n.key = 9, n.kind = ItemKind::kExpired;
  EXPECT_EQ(c.put(n), Custody::Put::kStored);  // notices have their own room
  EXPECT_EQ(c.data(), 2u);
  EXPECT_EQ(c.notices(), 1u);
  const int32_t keys[] = {5, 42};
  EXPECT_EQ(c.acked(keys, 2), 1u);
  EXPECT_FALSE(c.holds(5));
  EXPECT_TRUE(c.holds(6));
  EXPECT_EQ(c.put(measured(7, 1, 3.0)), Custody::Put::kStored);
}

TEST(Custody, SendsWhatIsDueAndResendsOnlyAfterTheInterval) {
  Custody c(8, 8);
  c.put(measured(1, 1, 0.0));
  c.put(measured(2, 1, 0.0));
  DataBatch b;
  EXPECT_EQ(c.due(10.0, 1.0, false, b), 2u);
  EXPECT_EQ(c.due(10.5, 1.0, false, b), 0u);  // sent 0.5 s ago, no ack yet: wait
  c.put(measured(3, 1, 0.0));
  EXPECT_EQ(c.due(10.6, 1.0, false, b), 1u);  // only the new one
  EXPECT_EQ(b.items[0].key, 3);
  EXPECT_EQ(c.due(11.0, 1.0, false, b), 2u);  // 1 and 2 again: the ack was lost
  EXPECT_EQ(c.due(11.1, 1.0, true, b), 3u);   // a new contact: everything
}

// A team on the corridor and its pieces.
struct CorridorTeam {
  Scenario scenario = corridor();
  mission::World world{scenario};
  mission::MissionPlan plan = corridor_plan(scenario);
  MissionParams params;
  std::unique_ptr<TeamSetup> team;
  explicit CorridorTeam(int cycles = 2, std::vector<std::pair<int, Point2>> goals = {}) {
    params.cycles = cycles;
    params.goals_per_request = 4;
    params.fixed_goals = std::move(goals);
    team = std::make_unique<TeamSetup>(world, plan, params);
  }
};

Message message(Kind kind, int16_t sender, int16_t dest, uint32_t seq, Point2 pos, int32_t request = 0) {
  Message m;
  m.h.kind = kind, m.h.sender = sender, m.h.dest = dest, m.h.seq = seq, m.h.pos = pos, m.h.request = request;
  return m;
}

TEST(RangeGate, HearsOnlyWhatTheRadioModelLinks) {
  CorridorTeam c;
  const RangeGate gate(*c.team);
  const Message m = message(Kind::kState, 0, kBroadcast, 0, Point2{1.0, 0.25});
  EXPECT_EQ(gate.admit(m.h, 1, Point2{2.5, 0.25}), RangeGate::Verdict::kPass);
  EXPECT_EQ(gate.admit(m.h, 1, Point2{4.0, 0.25}), RangeGate::Verdict::kOutOfRange);  // 3 m: beyond 2.07 m
}

TEST(RangeGate, AWallInBetweenCutsALinkThatWouldHoldInTheOpen) {
  // 1.5 m apart: -45.3 dBm in the open (sensitivity -49.5), -50.3 through
  // one wall (5 dB). The wall at x = 2.0..2.1 m leaves a gap at the bottom row.
  Scenario s = corridor();
  std::vector<int8_t> v(s.grid.values());
  std::vector<uint8_t> f(s.grid.free_mask());
  for (int r = 1; r < 5; ++r)
    v[static_cast<std::size_t>(r) * 200 + 20] = 100, f[static_cast<std::size_t>(r) * 200 + 20] = 0;
  s.grid = OccupancyGrid(200, 5, 0.1, Point2{0, 0}, v, f);
  const mission::World world(s);
  MissionParams prm;
  prm.cycles = 1;
  TeamSetup team(world, corridor_plan(s), prm);
  const RangeGate gate(team);
  const Message through = message(Kind::kState, 0, kBroadcast, 0, Point2{1.3, 0.25});
  EXPECT_EQ(gate.admit(through.h, 1, Point2{2.8, 0.25}), RangeGate::Verdict::kOutOfRange);
  const Message open = message(Kind::kState, 0, kBroadcast, 0, Point2{1.3, 0.05});  // both in the gap's row
  EXPECT_EQ(gate.admit(open.h, 1, Point2{2.8, 0.05}), RangeGate::Verdict::kPass);
}

TEST(RangeGate, InjectedLossIsSeededAndAtTheRequestedRate) {
  CorridorTeam c;
  const RangeGate a(*c.team, 0.3, 7), b(*c.team, 0.3, 7), other(*c.team, 0.3, 8);
  int lost = 0, same = 0, differ = 0;
  for (uint32_t seq = 0; seq < 4000; ++seq) {
    const Message m = message(Kind::kState, 0, kBroadcast, seq, Point2{1.0, 0.25});
    const auto va = a.admit(m.h, 1, Point2{1.5, 0.25});
    lost += va == RangeGate::Verdict::kLost;
    same += va == b.admit(m.h, 1, Point2{1.5, 0.25});
    differ += va != other.admit(m.h, 1, Point2{1.5, 0.25});
  }
  EXPECT_NEAR(lost / 4000.0, 0.3, 0.03);
  EXPECT_EQ(same, 4000);  // same seed: same losses, whatever the order
  EXPECT_GT(differ, 500);
}

TEST(Inbox, AddressedInRangeInSenderSeqOrderOwnSkippedOverflowCounted) {
  CorridorTeam c;
  const RangeGate gate(*c.team);
  std::vector<Message> sent = {
      message(Kind::kState, 0, kBroadcast, 3, {1, 0.25}), message(Kind::kAck, kOc, 1, 9, {0.55, 0.25}),
      message(Kind::kState, 0, kBroadcast, 2, {1, 0.25}), message(Kind::kAck, kOc, 0, 8, {0.55, 0.25}),  // for agent 0
      message(Kind::kState, 1, kBroadcast, 4, {1, 0.25}),                                                // its own
      message(Kind::kState, 0, kBroadcast, 1, {9, 0.25}),                                                // out of range
  };
  LinkCounters link;
  std::vector<const Message*> inbox;
  inbox.reserve(8);
  gather_inbox(sent, 1, Point2{1.2, 0.25}, gate, link, inbox);
  ASSERT_EQ(inbox.size(), 3u);
  EXPECT_EQ(inbox[0]->h.sender, kOc);
  EXPECT_EQ(inbox[1]->h.seq, 2u);
  EXPECT_EQ(inbox[2]->h.seq, 3u);
  EXPECT_EQ(link.received, 3);
  EXPECT_EQ(link.gated, 1);
  std::vector<const Message*> small;
  small.reserve(1);
  LinkCounters l2;
  gather_inbox(sent, 1, Point2{1.2, 0.25}, gate, l2, small);
  EXPECT_EQ(small.size(), 1u);
  EXPECT_EQ(l2.overflow, 2);
}

// A role alone, stepped by hand every 0.1 s.
struct Stepper {
  explicit Stepper(AgentUnit u) : unit(std::move(u)) {}
  AgentUnit unit;
  Outbox out{64};
  std::vector<Message> inbox_store;
  std::vector<const Message*> inbox;
  void step(double t, std::vector<Message> in = {}) {
    unit.motion->advance(t);
    inbox_store = std::move(in);
    inbox.clear();
    for (const Message& m : inbox_store) inbox.push_back(&m);
    out.clear();
    unit.role->step(t, inbox.data(), inbox.size(), out);
  }
  const Message* sent(Kind k) const {
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i].h.kind == k) return &out[i];
    return nullptr;
  }
};

Message request(int32_t id, int32_t first, std::vector<Point2> goals, const OccupancyGrid& grid, int16_t from,
                int16_t to) {
  Message m = message(Kind::kRequest, from, to, 0, Point2{0.55, 0.25}, id);
  m.request = RequestPart{};
  m.request.request = id, m.request.first_goal = first, m.request.total = static_cast<int32_t>(goals.size());
  m.request.part = 0, m.request.parts = 1, m.request.count = static_cast<uint16_t>(goals.size());
  for (std::size_t i = 0; i < goals.size(); ++i)
    m.request.cells[i] = static_cast<uint32_t>(grid.index(grid.world_to_cell(goals[i])));
  return m;
}

TEST(WorkerRole, MeasuresHandsOverInContactResendsALostAckAndReportsExpiry) {
  CorridorTeam c(3);
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper w{make_agent(*c.team, AgentId(1))};
  // Request 0 from the OC: goals at x = 5.05 (4.5 m from the OC) and 19.05.
  w.step(0.0, {request(0, 0, {{5.05, 0.25}, {19.05, 0.25}}, grid, kOc, kBroadcast)});
  auto& role = static_cast<WorkerRole&>(*w.unit.role);
  EXPECT_EQ(role.phase(), WorkerRole::Phase::kMoving);
  const Message* data = nullptr;
  double t = 0.0;
  for (; t < 10.0 && !data; t += 0.1) {
    w.step(t);
    data = w.sent(Kind::kData);
  }
  // Measured on arrival (about 4.5 m at 1 m/s from its start next to the OC),
  // in radio contact with the collector driving alongside: sent at once.
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(data->h.dest, 0);
  ASSERT_EQ(data->data.count, 1u);
  EXPECT_EQ(data->data.items[0].key, 0);
  // Measured on arrival: it heard the request at t = 0.1 s and walked from
  // its start pose at 1 m/s.
  const double walk = 5.05 - c.team->start_pose(AgentId(1)).x;
  EXPECT_NEAR(data->data.items[0].at, 0.1 + walk, 0.15);
  const double first = t;
  // No ack: sent again after resend_after (1 s) while in contact.
  double again = -1;
  for (; t < first + 3.0 && again < 0; t += 0.1) {
    w.step(t);
    if (w.sent(Kind::kData)) again = t;
  }
  EXPECT_NEAR(again - first, 1.0, 0.15);
  Message ack = message(Kind::kAck, 0, 1, 1, w.unit.motion->pose());
  ack.ack.count = 1, ack.ack.keys[0] = 0;
  w.step(t, {ack});
  EXPECT_EQ(role.custody()->data(), 0u);
  // The goal at 19.05 cannot be measured before the collector brings request
  // 1 (114.5 s): unless the worker gets there, it expires then, as a notice.
  for (t += 0.1; t < 130.0; t += 0.1) w.step(t);
  const RoleReport r = role.report();
  EXPECT_EQ(r.measured + r.expired, 2);
}

TEST(CollectorRole, AcksStoresOnceRefusesWhenFullDeliversInCoverageRelaysRequests) {
  CorridorTeam c(2);
  c.team->params.data_capacity = 2;
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper k{make_agent(*c.team, AgentId(0))};
  k.step(0.0, {request(0, 0, {{19.05, 0.25}}, grid, kOc, kBroadcast)});
  // Its worker's data at t = 5 s (both at x ~ 5.5 m): acked, picked up now.
  Message d = message(Kind::kData, 1, 0, 0, Point2{5.5, 0.25});
  d.data.count = 1, d.data.items[0] = measured(0, 1, 4.5);
  k.step(5.0, {d});
  const Message* ack = k.sent(Kind::kAck);
  ASSERT_NE(ack, nullptr);
  EXPECT_EQ(ack->ack.count, 1u);
  // The same item again (its ack was lost): acked again, stored once.
  k.step(5.1, {d});
  ASSERT_NE(k.sent(Kind::kAck), nullptr);
  EXPECT_EQ(k.unit.role->custody()->data(), 1u);
  EXPECT_EQ(k.unit.role->custody()->item(0).picked_up_by, 0);
  EXPECT_NEAR(k.unit.role->custody()->item(0).picked_up_at, 5.0, 1e-9);
  // Two more: one fits (capacity 2), the other is refused and not acked.
  Message two = message(Kind::kData, 1, 0, 1, Point2{5.7, 0.25});
  two.data.count = 2, two.data.items[0] = measured(1, 1, 5.0), two.data.items[1] = measured(2, 1, 5.1);
  k.step(5.2, {two});
  ASSERT_NE(k.sent(Kind::kAck), nullptr);
  EXPECT_EQ(k.sent(Kind::kAck)->ack.count, 1u);
  EXPECT_EQ(k.unit.role->report().refused_full, 1);
  // The meeting area (arc 14.5 m) at 14.5 s: request 0 goes to the worker.
  bool relayed = false, delivered_early = false;
  double t = 5.3;
  for (; t < 15.0; t += 0.1) {
    k.step(t);
    if (const Message* r = k.sent(Kind::kRequest)) relayed = relayed || (r->h.dest == 1 && std::abs(t - 14.5) < 0.15);
    delivered_early = delivered_early || k.sent(Kind::kData);
  }
  EXPECT_TRUE(relayed);
  EXPECT_FALSE(delivered_early);  // out of the OC's coverage all along
  // Back in the coverage at 26.95 s: its data goes to the OC.
  double delivered = -1;
  for (; t < 30.0 && delivered < 0; t += 0.1) {
    k.step(t);
    if (const Message* m = k.sent(Kind::kData)) {
      delivered = t;
      EXPECT_EQ(m->h.dest, kOc);
    }
  }
  EXPECT_NEAR(delivered, 26.95, 0.15);
}

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
}

// The whole team on the corridor: the simulator's hand-computed times
// (tests/core/mission_test.cpp) up to the tick and message latencies.
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
    EXPECT_GT(lost, 100);
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

TEST(WorkerRole, IgnoresARequestLargerThanTheMissionsOwn) {
  CorridorTeam c(3);  // goals_per_request 4
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper w{make_agent(*c.team, AgentId(1))};
  std::vector<Point2> five = {{3.05, 0.25}, {4.05, 0.25}, {5.05, 0.25}, {6.05, 0.25}, {7.05, 0.25}};
  w.step(0.0, {request(0, 0, five, grid, kOc, kBroadcast)});
  EXPECT_EQ(static_cast<WorkerRole&>(*w.unit.role).phase(), WorkerRole::Phase::kStart);
  EXPECT_EQ(w.unit.role->newest_request(), -1);
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

namespace gather {
namespace agent {
namespace {

TEST(RunFiles, WritesTheSimulatorsSchemaAndAMissionFile) {
  CorridorTeam c(2, {{0, Point2{5.05, 0.25}}, {1, Point2{9.05, 0.25}}});
  const RunOutcome out = TeamRunner(*c.team, RunOptions{}).run();
  ASSERT_TRUE(out.completed);
  RunFiles files;
  files.add(c.plan.file, c.team->params, out);
  const std::string dir = ::testing::TempDir() + "/gather_run_files_test";
  files.write(dir);
  auto first_line = [](const std::string& path) {
    std::ifstream in(path);
    std::string l;
    std::getline(in, l);
    return l + "\n";
  };
  EXPECT_EQ(first_line(dir + "/goals.csv"), mission::kGoalsCsvHeader);
  EXPECT_EQ(first_line(dir + "/cycles.csv"), mission::kCyclesCsvHeader);
  EXPECT_EQ(first_line(dir + "/summary.csv"), mission::kSummaryCsvHeader);
  EXPECT_EQ(first_line(dir + "/agents.csv"), kAgentsCsvHeader);
  LoadedPlan lp;
  lp.dir = dir, lp.plan = c.plan, lp.scenario = c.scenario;
  write_mission_yaml(dir + "/mission.yaml", lp, c.team->params, RunSettings{"in-process", 0.1, 0.0, 0.0}, out);
  std::ifstream in(dir + "/mission.yaml");
  const std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(yaml.find("status: ok"), std::string::npos);
  EXPECT_NE(yaml.find("requested: 2, delivered: 2"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("role: collector"), std::string::npos);
}

}  // namespace
}  // namespace agent
}  // namespace gather
