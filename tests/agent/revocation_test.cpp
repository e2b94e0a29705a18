// Revocation (docs/security.md, "Revocation"): the OC retires an agent's
// keys during the mission. From then on the OC, and every agent once it
// learns it from a request, drop that agent's messages and count them; the
// OC refuses what others hand in of what it held then; every such goal ends
// lost with it, and the runner's conservation and lost-goal checks still
// hold (its process keeps running and keeps what it holds).
#include <gtest/gtest.h>

#include <vector>

#include "corridor_team.hpp"
#include "gather_agent/motion/motion_backend.hpp"
#include "gather_agent/roles/role.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/repair.hpp"
#include "office_team.hpp"

namespace gather {
namespace agent {
namespace {

using testing_support::a_worker;
using testing_support::busiest_collector;
using testing_support::Office;

// A role that records whom it heard.
class Probe : public Role {
 public:
  explicit Probe(MotionBackend& m) : Role(0, m) {}
  void step(double, const Message* const* inbox, std::size_t n, Outbox&) override {
    for (std::size_t i = 0; i < n; ++i) heard.push_back(inbox[i]->h.sender);
  }
  RoleKind kind() const override { return RoleKind::kWorker; }
  RoleReport report() const override { return {}; }
  int32_t newest_request() const override { return -1; }
  bool learn(const RequestPart& p) { return learn_dead(p); }
  std::vector<int16_t> heard;
};

RequestPart declarations(std::vector<int16_t> dead, uint32_t revoked) {
  RequestPart p;
  p.dead_count = static_cast<uint8_t>(dead.size());
  for (std::size_t i = 0; i < dead.size(); ++i) p.dead[i] = dead[i];
  p.dead_revoked = revoked;
  return p;
}

TEST(Revocation, AnAgentLearnsItFromARequestAndDropsAndCountsTheRevokedAgentsMessages) {
  Station st(Point2{0.0, 0.0});
  Probe p(st);
  Outbox out(4);
  EXPECT_TRUE(p.learn(declarations({3, 5}, 2)));  // 5 revoked, 3 only dead
  EXPECT_TRUE(p.revoked(5));
  EXPECT_FALSE(p.revoked(3));
  const uint64_t version = p.progress_version();
  std::vector<Message> inbox(4);
  inbox[0].h.sender = 3, inbox[1].h.sender = 5, inbox[2].h.sender = kOc, inbox[3].h.sender = 5;
  const Message* ptrs[] = {&inbox[0], &inbox[1], &inbox[2], &inbox[3]};
  p.control(1.0, ptrs, 4, out);
  EXPECT_EQ(p.heard, (std::vector<int16_t>{3, kOc}));
  EXPECT_EQ(p.refused_revoked(1), 2);
  EXPECT_EQ(p.refused_revoked(0), 0);
  EXPECT_EQ(p.refused_revoked(), 2);
  // 3, declared dead before, revoked later: learned without a new declaration.
  EXPECT_FALSE(p.learn(declarations({3, 5}, 3)));
  EXPECT_TRUE(p.revoked(3));
  EXPECT_GT(p.progress_version(), version);  // journaled
  // An older list changes nothing; a bit beyond the list is not taken.
  EXPECT_FALSE(p.learn(declarations({3}, 0)));
  EXPECT_EQ(p.revoked_mask(), 3u);
  EXPECT_TRUE(p.learn(declarations({3, 5, 8}, 3 | 8)));
  EXPECT_EQ(p.revoked_mask(), 3u);
  Progress saved;
  p.progress(saved);
  EXPECT_EQ(saved.revoked, 3u);
  EXPECT_EQ(saved.dead, (std::vector<int16_t>{3, 5, 8}));
}

RunOutcome run(const mission::MissionPlan& plan, int cycles, std::vector<std::pair<int16_t, double>> revoke,
               double loss) {
  MissionParams p = testing_support::office_params(cycles, 1);
  p.revoke = std::move(revoke);
  TeamSetup team(Office::get().ctx, plan, p);
  RunOptions opt;
  opt.loss = loss, opt.loss_seed = 1;
  return TeamRunner(team, opt).run();  // conservation every cycle; lost goals against the ground truth at the end
}

int delivered(const RunOutcome& out) {
  int n = 0;
  for (const mission::GoalRecord& g : out.result.goals) n += g.state == mission::GoalState::kDelivered;
  return n;
}

TEST(Revocation, ARevokedWorkerOfACollectorIsCutOffAndOnlyWhatItHeldIsLost) {
  const mission::MissionPlan& plan = Office::get().pap4;
  const AgentId victim = a_worker(plan, false);
  const int collector = mission::collector_agents(plan.file)[plan.file.agents[victim].delivers_to].value();
  const double at = 2.3 * plan.file.cycle_period_s;
  const RunOutcome base = run(plan, 6, {}, 0.2);
  const RunOutcome out = run(plan, 6, {{static_cast<int16_t>(victim.value()), at}}, 0.2);
  ASSERT_TRUE(out.completed) << out.failure;
  ASSERT_EQ(out.revoked.size(), 1u);
  EXPECT_EQ(out.revoked[0].agent, victim.value());
  EXPECT_NEAR(out.revoked[0].at, at, 0.11);
  ASSERT_EQ(out.declared_dead.size(), 1u);  // declared at once, not after a timeout
  EXPECT_EQ(out.declared_dead[0].first, victim.value());
  EXPECT_EQ(out.declared_dead[0].second, out.revoked[0].at);
  // Its collector learned it and dropped its messages; it kept talking.
  EXPECT_GT(out.agents[static_cast<std::size_t>(collector)].report.refused_revoked, 0);
  int measured_after = 0;
  for (const mission::GoalRecord& g : out.result.goals) {
    if (g.measured_by != victim || g.state != mission::GoalState::kDelivered) continue;
    // Delivered only what it handed over before the revocation: to its
    // collector, or (its collector silent for long) to the OC.
    EXPECT_LE(g.picked_up_by.valid() ? g.picked_up_at : g.delivered_at, out.revoked[0].at + 1e-9) << g.id;
    measured_after += g.measured_at > out.revoked[0].at;
  }
  EXPECT_EQ(measured_after, 0);
  EXPECT_EQ(out.invalid_items, 0);
  EXPECT_GE(delivered(out), 0.85 * delivered(base)) << "without the revocation " << delivered(base);
}

TEST(Revocation, ARevokedCollectorDeliversNothingMoreAndItsCargoIsLost) {
  const mission::MissionPlan& plan = Office::get().pap4;
  const CollectorId c = busiest_collector(plan);
  const AgentId victim = mission::collector_agents(plan.file)[c];
  const double at = 2.6 * plan.file.cycle_period_s;
  const RunOutcome out = run(plan, 6, {{static_cast<int16_t>(victim.value()), at}}, 0.0);
  ASSERT_TRUE(out.completed) << out.failure;
  ASSERT_EQ(out.revoked.size(), 1u);
  EXPECT_GT(out.revoked[0].oc_refused, 0);  // it kept handing in
  int lost = 0;
  for (const mission::GoalRecord& g : out.result.goals) {
    if (g.state == mission::GoalState::kDelivered) {
      EXPECT_TRUE(g.delivered_by != victim || g.delivered_at <= out.revoked[0].at + 1e-9) << g.id;
    }
    lost += g.state == mission::GoalState::kLostWithAgent;
  }
  EXPECT_GT(lost, 0);
}

// A reachable cell of `segment` in the plan (the first in row-major order),
// as a point of the map.
Point2 a_point_of(const TeamSetup& team, SegmentId segment) {
  const LabelImage& labels = team.plan.labels;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == segment.label() && team.world.reaches(labels.frame().cell(i)))
      return team.world.scenario.grid.cell_center(labels.frame().cell(i));
  ADD_FAILURE() << "no reachable cell in " << to_string(segment);
  return Point2{};
}

// Claims of goals a worker never measured (item 5 of the issue): the OC
// takes a measurement from a worker only of a cell a plan or a repair could
// have given it. Here worker X gives a goal up, the OC then declares X (a
// revocation, at once), and X's segment goes to its neighbour B: B's
// measurement of it is real and delivered (overridden); the same claim by
// another worker Z, or B's claim of a goal in Z's segment, is refused.
TEST(Revocation, AClaimOfAGoalNoPlanGaveTheClaimantIsRefused) {
  const mission::MissionPlan& plan = Office::get().pap4;
  const AgentId x = a_worker(plan, true);
  MissionParams p = testing_support::office_params(1, 1);
  TeamSetup probe(Office::get().ctx, plan, p);
  const SegmentId sx = plan.file.agents[x].segment;
  const Point2 px = a_point_of(probe, sx);
  const int16_t dead[] = {static_cast<int16_t>(x.value())};
  const Cell cx = probe.world.scenario.grid.world_to_cell(px);
  const AgentId b = probe.worker_of_segment(SegmentId(probe.repaired(dead, 1).plan.labels.at(cx)));
  ASSERT_TRUE(b.valid());
  ASSERT_NE(b, x);
  AgentId z;
  for (const plan::AgentAssignment& a : plan.file.agents)
    if (!a.collector && a.id != x && a.id != b) z = a.id;
  ASSERT_TRUE(z.valid());
  p.fixed_goals = {{0, px}, {0, a_point_of(probe, plan.file.agents[z].segment)}};
  p.goals_per_request = 2;
  p.revoke = {{static_cast<int16_t>(x.value()), 3.0}};
  TeamSetup team(Office::get().ctx, plan, p);
  agent_testing::Stepper oc{make_oc(team)};
  auto& role = static_cast<OcRole&>(*oc.unit.role);
  oc.step(0.0);
  auto data = [&](AgentId from, DataItem item, uint32_t seq) {
    Message m = agent_testing::message(Kind::kData, static_cast<int16_t>(from.value()), kOc, seq, Point2{});
    m.data.count = 1, m.data.items[0] = item;
    return m;
  };
  DataItem gave_up;
  gave_up.key = 0, gave_up.kind = ItemKind::kExpired, gave_up.by = static_cast<int16_t>(x.value()), gave_up.at = 1.5;
  gave_up.deadline = 1.5;
  oc.step(2.0, {data(x, gave_up, 0)});
  ASSERT_EQ(role.goals()[0].state, mission::GoalState::kExpired);
  oc.step(3.0);  // X revoked: declared dead, its segment merged into B's
  ASSERT_DOUBLE_EQ(role.declared_dead_at(x), 3.0);
  const auto zi = static_cast<int16_t>(z.value()), bi = static_cast<int16_t>(b.value());
  oc.step(4.0, {data(z, agent_testing::measured(0, zi, 3.5), 0)});
  EXPECT_EQ(role.invalid_items(), 1);
  EXPECT_EQ(role.goals()[0].state, mission::GoalState::kExpired);
  oc.step(5.0, {data(b, agent_testing::measured(1, bi, 4.5), 0)});
  EXPECT_EQ(role.invalid_items(), 2);
  EXPECT_FALSE(role.resolved(GoalId(1)));
  oc.step(6.0, {data(b, agent_testing::measured(0, bi, 5.5), 1)});
  EXPECT_EQ(role.invalid_items(), 2);
  EXPECT_EQ(role.goals()[0].state, mission::GoalState::kDelivered);
  EXPECT_EQ(role.goals()[0].measured_by, b);
  EXPECT_EQ(role.overridden(), 1);
}

TEST(Revocation, ParsesLikeKillsAndRefusesAnAgentNamedTwice) {
  EXPECT_THROW(parse_kills("3@10,3@20", 20, "--revoke"), Error);
  EXPECT_THROW(parse_kills("20@10", 20, "--revoke"), Error);
  EXPECT_EQ(parse_kills("none", 20, "--revoke").size(), 0u);
}

}  // namespace
}  // namespace agent
}  // namespace gather
