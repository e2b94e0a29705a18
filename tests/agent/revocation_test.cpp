// Revocation (docs/security.md, "Revocation"): the OC retires an agent's
// keys during the mission. From then on the OC, and every agent once it
// learns it from a request, drop that agent's messages and count them; the
// OC refuses what others hand in of what it held then; every such goal ends
// lost with it, and the runner's conservation and lost-goal checks still
// hold (its process keeps running and keeps what it holds).
#include <gtest/gtest.h>

#include <vector>

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

TEST(Revocation, ParsesLikeKillsAndRefusesAnAgentNamedTwice) {
  EXPECT_THROW(parse_kills("3@10,3@20", 20, "--revoke"), Error);
  EXPECT_THROW(parse_kills("20@10", 20, "--revoke"), Error);
  EXPECT_EQ(parse_kills("none", 20, "--revoke").size(), 0u);
}

}  // namespace
}  // namespace agent
}  // namespace gather
