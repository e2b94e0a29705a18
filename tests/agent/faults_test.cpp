// Faults of the team (docs/faults.md): --kill's parsing, and whole missions on maps/office
// where a worker or a collector dies: the OC declares it dead, the
// survivors run the repaired plan, and every goal it took with it ends as
// lost_with_agent (checked against the ground truth by the runner), none
// silently, none twice.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "gather_agent/roles/worker_role.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/repair.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "office_team.hpp"

namespace gather {
namespace agent {
namespace {

using testing_support::a_worker;
using testing_support::busiest_collector;
using testing_support::Office;

MissionParams params(int cycles, unsigned seed) { return testing_support::office_params(cycles, seed); }

TEST(Kill, ParsesIdAtTimeAndRefusesTheRest) {
  const Kill k = parse_kill("3@120.5", 20, "--kill");
  EXPECT_EQ(k.agent, 3);
  EXPECT_DOUBLE_EQ(k.at, 120.5);
  for (const char* bad : {"3", "@5", "3@", "x@5", "3@5s", "20@5", "-1@5", "3@-1", "3@nan", "3@inf"})
    EXPECT_THROW(parse_kill(bad, 20, "--kill"), Error) << bad;
}

struct Counts {
  int delivered = 0, expired = 0, dropped = 0, lost = 0;
};
Counts counts(const RunOutcome& out) {
  Counts c;
  for (const mission::GoalRecord& g : out.result.goals) {
    c.delivered += g.state == mission::GoalState::kDelivered;
    c.expired += g.state == mission::GoalState::kExpired;
    c.dropped += g.state == mission::GoalState::kDropped;
    c.lost += g.state == mission::GoalState::kLostWithAgent;
  }
  return c;
}

RunOutcome run(const mission::MissionPlan& plan, int cycles, unsigned seed, std::vector<Kill> kills, double loss = 0.0,
               mission::RepairMode mode = mission::RepairMode::kMerge) {
  MissionParams p = params(cycles, seed);
  p.repair = mode;
  TeamSetup team(Office::get().ctx, plan, p);
  RunOptions opt;
  opt.kills = std::move(kills);
  opt.loss = loss, opt.loss_seed = seed;
  return TeamRunner(team, opt).run();  // conservation every cycle; lost goals against the ground truth at the end
}

TEST(Faults, NoFaultNoDeclarationEvenWithALossyRadio) {
  for (const mission::MissionPlan* plan : {&Office::get().pap4, &Office::get().bap0}) {
    const RunOutcome out = run(*plan, 6, 2, {}, 0.3);
    ASSERT_TRUE(out.completed) << out.failure;
    EXPECT_TRUE(out.declared_dead.empty()) << plan->file.method << ": agent " << out.declared_dead[0].first << " at "
                                           << out.declared_dead[0].second << " s";
    EXPECT_EQ(counts(out).lost, 0);
  }
}

TEST(Faults, ADeadWorkerIsDeclaredItsSegmentMergedItsGoalsLostWithItOnly) {
  const mission::MissionPlan& plan = Office::get().bap0;
  const AgentId worker = a_worker(plan, true);
  const int victim = worker.value();
  const double period = plan.file.cycle_period_s;
  const double kill_at = 2.5 * period;
  const RunOutcome out = run(plan, 10, 1, {{victim, kill_at}});
  ASSERT_TRUE(out.completed) << out.failure;
  ASSERT_EQ(out.declared_dead.size(), 1u);
  EXPECT_EQ(out.declared_dead[0].first, victim);
  const double declared = out.declared_dead[0].second;
  EXPECT_GT(declared, kill_at);
  EXPECT_LE(declared, kill_at + 3.0 * period + 1.0);  // 3 request periods unheard, for a worker of the OC
  const Counts c = counts(out);
  EXPECT_GT(c.lost, 0);
  const int s = plan.file.agents[worker].segment.label();
  const OccupancyGrid& grid = Office::get().scenario.grid;
  auto in_s = [&](const mission::GoalRecord& g) {
    return plan.labels[static_cast<std::size_t>(grid.index(grid.world_to_cell(g.point)))] == s;
  };
  int after_in_s = 0, after_in_s_delivered = 0;
  for (const mission::GoalRecord& g : out.result.goals) {
    if (g.state == mission::GoalState::kLostWithAgent) {
      EXPECT_EQ(g.worker, worker) << g.id;
      EXPECT_LE(g.requested_at, declared) << g.id;
    }
    if (g.requested_at > declared && in_s(g)) {
      ++after_in_s;
      EXPECT_NE(g.worker, worker);
      after_in_s_delivered += g.state == mission::GoalState::kDelivered;
    }
  }
  EXPECT_GT(after_in_s, 0);
  EXPECT_GT(after_in_s_delivered, 0);  // its neighbour serves the merged segment
  // Leaving the segment to nobody: its goals after the declaration expire
  // (docs/faults_bench.md compares the two over seeds).
  const RunOutcome none = run(plan, 10, 1, {{victim, kill_at}}, 0.0, mission::RepairMode::kNone);
  ASSERT_TRUE(none.completed) << none.failure;
  for (const mission::GoalRecord& g : none.result.goals)
    if (g.requested_at > declared && in_s(g)) {
      EXPECT_EQ(g.state, mission::GoalState::kExpired) << g.id;
    }
}

TEST(Faults, ADeadCollectorsWorkersComeToTheOcAndOnlyItsCargoIsLost) {
  const mission::MissionPlan& plan = Office::get().pap4;
  const double period = plan.file.cycle_period_s;
  const RunOutcome base = run(plan, 10, 1, {});
  ASSERT_TRUE(base.completed) << base.failure;
  const CollectorId collector = busiest_collector(plan);
  const int victim = mission::collector_agents(plan.file)[collector].value();
  const RunOutcome out = run(plan, 10, 1, {{victim, 3.3 * period}}, 0.2);
  ASSERT_TRUE(out.completed) << out.failure;
  ASSERT_EQ(out.declared_dead.size(), 1u) << "agent " << out.declared_dead[1].first;
  EXPECT_EQ(out.declared_dead[0].first, victim);
  const double declared = out.declared_dead[0].second;
  // Its workers deliver to the OC themselves after that.
  int direct = 0;
  for (const mission::GoalRecord& g : out.result.goals)
    if (g.requested_at > declared && g.state == mission::GoalState::kDelivered && g.worker.valid() &&
        plan.file.agents[g.worker].delivers_to == collector) {
      EXPECT_EQ(g.delivered_by, g.worker);
      ++direct;
    }
  EXPECT_GT(direct, 0);
  const Counts c = counts(out), b = counts(base);
  EXPECT_GE(c.delivered, 0.9 * b.delivered) << "fault-free " << b.delivered;
  EXPECT_EQ(out.invalid_items, 0);
}

TEST(Faults, AWorkerOfACollectorDiesUnderLossAndTheMissionGoesOn) {
  const mission::MissionPlan& plan = Office::get().pap4;
  const int victim = a_worker(plan, false).value();
  const RunOutcome base = run(plan, 10, 3, {});
  const RunOutcome out = run(plan, 10, 3, {{victim, 4.1 * plan.file.cycle_period_s}}, 0.2);
  ASSERT_TRUE(out.completed) << out.failure;
  ASSERT_EQ(out.declared_dead.size(), 1u);
  EXPECT_EQ(out.declared_dead[0].first, victim);
  EXPECT_GE(counts(out).delivered, 0.9 * counts(base).delivered);
}

}  // namespace
}  // namespace agent
}  // namespace gather
