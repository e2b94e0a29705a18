// mission/repair: the survivors' plan as a pure function of the dead set
// (a dead worker's segment merged into its smallest live neighbour, or left
// to nobody; a dead collector's workers deliver to the OC), and the OC's
// liveness timeouts. On maps/office's plans.
#include "gather_core/mission/repair.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "office_team.hpp"

namespace gather {
namespace {

using testing_support::a_worker;
using testing_support::busiest_collector;
using testing_support::Office;

int64_t cells_of(const mission::MissionPlan& p, int32_t label) {
  return std::count(p.labels.begin(), p.labels.end(), label);
}

TEST(RepairPlan, ADeadWorkersSegmentGoesToItsSmallestLiveNeighbour) {
  const mission::MissionPlan& base = Office::get().bap0;
  const AgentId dead = a_worker(base, true);
  const SegmentId seg = base.file.agents[dead].segment;
  const int s = seg.label();
  const mission::RepairedPlan r = mission::repair_plan(base, {dead}, mission::RepairMode::kMerge);
  EXPECT_EQ(cells_of(r.plan, s), 0);
  EXPECT_TRUE(r.dead[dead]);
  const AgentId into_worker = r.worker_of_segment[seg];
  ASSERT_TRUE(into_worker.valid());
  ASSERT_NE(into_worker, dead);
  const int into = base.file.agents[into_worker].segment.label();
  EXPECT_EQ(cells_of(r.plan, into), cells_of(base, into) + cells_of(base, s));
  // No other neighbour of s is smaller than the one chosen.
  const int w = base.labels.width(), h = base.labels.height();
  std::set<int32_t> touching;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      const int32_t a = base.labels[static_cast<std::size_t>(y) * w + x],
                    b = base.labels[static_cast<std::size_t>(y) * w + x + 1];
      if (a == s && b > 0 && b != s) touching.insert(b);
      if (b == s && a > 0 && a != s) touching.insert(a);
    }
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int32_t a = base.labels[static_cast<std::size_t>(y) * w + x],
                    b = base.labels[static_cast<std::size_t>(y + 1) * w + x];
      if (a == s && b > 0 && b != s) touching.insert(b);
      if (b == s && a > 0 && a != s) touching.insert(a);
    }
  ASSERT_TRUE(touching.count(into));
  for (int32_t t : touching) EXPECT_GE(cells_of(base, t), cells_of(base, into)) << "segment " << t;
  // Other segments and every assignment are unchanged.
  for (std::size_t i = 0; i < base.labels.size(); ++i)
    if (base.labels[i] != s) {
      EXPECT_EQ(r.plan.labels[i], base.labels[i]);
    }
  for (AgentId a : ids<AgentId>(base.file.agents.count()))
    EXPECT_EQ(r.plan.file.agents[a].delivers_to, base.file.agents[a].delivers_to);
}

TEST(RepairPlan, NoneLeavesTheSegmentToNobodyAndTheSetOrderDoesNotMatter) {
  const mission::MissionPlan& base = Office::get().bap0;
  const AgentId a(3), b(7);
  const mission::RepairedPlan none = mission::repair_plan(base, {a}, mission::RepairMode::kNone);
  EXPECT_EQ(cells_of(none.plan, base.file.agents[a].segment.label()), 0);
  EXPECT_FALSE(none.worker_of_segment[base.file.agents[a].segment].valid());
  const mission::RepairedPlan ab = mission::repair_plan(base, {a, b}, mission::RepairMode::kMerge);
  const mission::RepairedPlan ba = mission::repair_plan(base, {b, a, b}, mission::RepairMode::kMerge);
  EXPECT_EQ(ab.plan.labels, ba.plan.labels);
  EXPECT_EQ(ab.worker_of_segment, ba.worker_of_segment);
  for (SegmentId seg : segment_ids(base.file.workers)) {
    const AgentId o = ab.worker_of_segment[seg];
    if (o.valid()) {
      EXPECT_FALSE(ab.dead[o]);
    }
  }
}

TEST(RepairPlan, ADeadCollectorsWorkersDeliverToTheOc) {
  const mission::MissionPlan& base = Office::get().pap4;
  const CollectorId c = busiest_collector(base);
  const AgentId driver = mission::collector_agents(base.file)[c];
  const mission::RepairedPlan r = mission::repair_plan(base, {driver}, mission::RepairMode::kMerge);
  int moved = 0;
  for (AgentId a : ids<AgentId>(base.file.agents.count())) {
    const plan::AgentAssignment& before = base.file.agents[a];
    const plan::AgentAssignment& after = r.plan.file.agents[a];
    if (!before.collector && before.delivers_to == c) {
      EXPECT_FALSE(after.delivers_to.valid());
      ++moved;
    } else {
      EXPECT_EQ(after.delivers_to, before.delivers_to);
    }
  }
  EXPECT_GT(moved, 0);
  EXPECT_EQ(r.plan.labels, base.labels);
}

TEST(Liveness, TimeoutsFollowEachRolesContactInterval) {
  EXPECT_DOUBLE_EQ(mission::silent_timeout(mission::Liveness::kCollector, 100, 80, 3), 240);
  EXPECT_DOUBLE_EQ(mission::silent_timeout(mission::Liveness::kOcWorker, 100, 80, 3), 300);
  EXPECT_DOUBLE_EQ(mission::silent_timeout(mission::Liveness::kCollectorWorker, 100, 80, 3), 540);
}

}  // namespace
}  // namespace gather
