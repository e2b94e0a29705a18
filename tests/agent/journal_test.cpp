// The agent's on-disk journal (docs/faults.md, "Crash and restart"): what
// is appended and synced comes back on replay, a torn or corrupt tail is cut
// off, another run's journal is not replayed, the file stays bounded; and a
// whole mission on maps/office where a worker of a collector crashes while
// it carries data and is started again from its journal: every goal it
// carried reaches the OC, once.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gather_agent/roles/worker_role.hpp"
#include "gather_agent/runner/journal.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "office_team.hpp"

namespace gather {
namespace agent {
namespace {

using testing_support::Office;
using testing_support::office_params;

std::string temp_dir(const std::string& name) {
  const std::string d = testing::TempDir() + "gather_journal_" + name + "_" + std::to_string(getpid());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

DataItem item(int32_t key, ItemKind kind = ItemKind::kMeasured) {
  DataItem it;
  it.key = key, it.kind = kind, it.by = 7, it.at = 12.5 + key, it.picked_up_by = -1, it.picked_up_at = -1.0;
  return it;
}

std::size_t file_size(const std::string& p) { return static_cast<std::size_t>(std::filesystem::file_size(p)); }

TEST(Journal, WhatIsSyncedComesBackOnReplay) {
  const std::string p = temp_dir("replay") + "/a.journal";
  Progress prog;
  prog.resolved = 3, prog.measured = 11, prog.expired = 2, prog.dead = {4}, prog.revoked = 1;
  prog.learned = {{GoalId(40), Cell{5, 6}, 100.0}, {GoalId(41), Cell{7, 8}, 100.0}};
  prog.known = {GoalId(41)};
  {
    Journal j(p, 7, 99);
    j.reset();
    for (int k = 0; k < 5; ++k) j.put(item(k));
    j.put(item(-5, ItemKind::kSkipped));
    j.acked(item(1));
    j.acked(item(3));
    j.progress(prog);
    j.pose(Point2{1.5, 2.5}, 30.0);
    EXPECT_TRUE(j.sync());
    EXPECT_FALSE(j.sync());  // nothing pending
  }
  Journal j(p, 7, 99);
  const JournalState s = j.replay();
  EXPECT_FALSE(s.cut);
  ASSERT_EQ(s.custody.size(), 4u);
  EXPECT_EQ(s.custody[0].key, 0);
  EXPECT_EQ(s.custody[1].key, 2);
  EXPECT_EQ(s.custody[2].key, 4);
  EXPECT_EQ(s.custody[3].kind, ItemKind::kSkipped);
  EXPECT_DOUBLE_EQ(s.custody[2].at, 16.5);
  ASSERT_TRUE(s.have_progress);
  EXPECT_EQ(s.progress.resolved, 3);
  EXPECT_EQ(s.progress.measured, 11);
  EXPECT_EQ(s.progress.dead, std::vector<int16_t>{4});
  EXPECT_EQ(s.progress.revoked, 1u);
  ASSERT_EQ(s.progress.learned.size(), 2u);
  EXPECT_EQ(s.progress.learned[1].cell.col, 8);
  EXPECT_EQ(s.progress.known, std::vector<GoalId>{GoalId(41)});
  ASSERT_TRUE(s.have_pose);
  EXPECT_DOUBLE_EQ(s.pose.y, 2.5);
  EXPECT_EQ(s.records, 10u);
  EXPECT_TRUE(s.matched);
}

TEST(Journal, ATornOrCorruptTailIsCutAndTheRestKept) {
  const std::string p = temp_dir("torn") + "/a.journal";
  std::size_t good = 0;
  {
    Journal j(p, 1, 5);
    j.reset();
    j.put(item(1));
    j.put(item(2));
    j.sync();
    good = file_size(p);
    // One step's records: an item and the progress that counts it.
    Progress prog;
    prog.measured = 3;
    j.put(item(3));
    j.progress(prog);
    j.sync();
  }
  // A crash in the middle of the last step's write: part of it is there,
  // the item's record whole. The step comes back whole or not at all.
  std::filesystem::resize_file(p, good + 9 + 9 + 30);
  {
    Journal j(p, 1, 5);
    const JournalState s = j.replay();
    EXPECT_TRUE(s.cut);
    ASSERT_EQ(s.custody.size(), 2u);
    EXPECT_FALSE(s.have_progress);
    EXPECT_EQ(file_size(p), good);
    j.put(item(4));  // appends after the good part
    j.sync();
  }
  {
    Journal j(p, 1, 5);
    const JournalState s = j.replay();
    EXPECT_FALSE(s.cut);
    ASSERT_EQ(s.custody.size(), 3u);
    EXPECT_EQ(s.custody[2].key, 4);
  }
  // A flipped bit in the first record: nothing after it is trusted.
  {
    std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(20 + 9 + 2);
    f.put('\x5a');
  }
  Journal j(p, 1, 5);
  const JournalState s = j.replay();
  EXPECT_TRUE(s.cut);
  EXPECT_TRUE(s.custody.empty());
}

TEST(Journal, AnotherRunsOrAgentsJournalIsNotReplayed) {
  const std::string d = temp_dir("run");
  auto write = [&](const std::string& p) {
    Journal j(p, 1, 5);
    j.reset();
    j.put(item(1));
    j.sync();
  };
  write(d + "/a.journal");
  write(d + "/b.journal");
  Journal other_run(d + "/a.journal", 1, 6);
  JournalState s = other_run.replay();
  EXPECT_FALSE(s.matched);
  EXPECT_TRUE(s.custody.empty());
  Journal other_agent(d + "/b.journal", 2, 5);
  s = other_agent.replay();
  EXPECT_FALSE(s.matched);
  EXPECT_TRUE(s.custody.empty());
  Journal same(d + "/b.journal", 2, 5);  // started afresh as agent 2's: nothing in it
  s = same.replay();
  EXPECT_TRUE(s.matched);
  EXPECT_TRUE(s.custody.empty());
}

TEST(Journal, CompactionKeepsItBoundedAndTheStateWhole) {
  const std::string p = temp_dir("compact") + "/a.journal";
  Journal j(p, 1, 5);
  j.reset();
  JournalState now;
  std::size_t largest = 0;
  int compactions = 0;
  for (int k = 0; k < 15000; ++k) {
    j.put(item(k));
    now.custody.push_back(item(k));
    if (k % 3 != 0) {
      j.acked(item(k));
      now.custody.pop_back();
    }
    if (k % 100 == 99) {
      j.sync();
      if (j.bytes() > Journal::kCompactBytes) j.compact(now), ++compactions;
      largest = std::max(largest, file_size(p));
    }
  }
  j.sync();
  EXPECT_GE(compactions, 1);
  // At most the bound, a step's records and the state carried (5000 items
  // of 34 bytes).
  EXPECT_LE(largest, Journal::kCompactBytes + 100 * 64 + 5000 * 34);
  Journal again(p, 1, 5);
  const JournalState s = again.replay();
  ASSERT_EQ(s.custody.size(), now.custody.size());
  EXPECT_EQ(s.custody.back().key, now.custody.back().key);
}

// The whole team on maps/office (pap:4, collectors busy), 20% loss: a worker
// of a collector crashes while it carries data and its process is started
// again at once from its journal. Everything it carried is delivered, once.
TEST(Restart, AWorkerCarryingDataCrashesAndItsDataStillArrivesOnce) {
  Office& o = Office::get();
  const mission::MissionPlan& plan = o.pap4;
  int victim = -1;
  for (const plan::AgentAssignment& a : plan.file.agents)
    if (!a.collector && a.delivers_to.valid() && victim < 0) victim = a.id.value();
  ASSERT_GE(victim, 0);
  // When does it first carry data (after the first minute)? The same run,
  // without a restart, up to then.
  std::vector<int32_t> carried;
  double at = -1.0;
  {
    TeamSetup team(o.ctx, plan, office_params(4, 2));
    RunOptions opt;
    opt.loss = 0.2, opt.loss_seed = 2;
    TeamRunner runner(team, opt);
    while (runner.tick()) {
      const Custody* c = runner.role(AgentId(victim)).custody();
      if (runner.now() > 60.0 && c->data() >= 2) {
        for (std::size_t i = 0; i < c->size(); ++i)
          if (c->item(i).kind == ItemKind::kMeasured) carried.push_back(c->item(i).key);
        at = runner.now();  // the tick after the one that left it carrying them
        break;
      }
    }
  }
  ASSERT_GE(at, 0.0) << "worker " << victim << " never carried data";
  TeamSetup team(o.ctx, plan, office_params(4, 2));
  RunOptions opt;
  opt.loss = 0.2, opt.loss_seed = 2;
  opt.restarts = {Kill{victim, at}};
  opt.journal_dir = temp_dir("restart");
  const RunOutcome out = TeamRunner(team, opt).run();  // conservation at every cycle's end
  ASSERT_TRUE(out.completed) << out.failure;
  EXPECT_TRUE(out.declared_dead.empty());
  for (int32_t key : carried) {
    const mission::GoalRecord& g = out.result.goals[static_cast<std::size_t>(key)];
    EXPECT_EQ(g.state, mission::GoalState::kDelivered) << "goal " << key << " carried at the crash";
    EXPECT_EQ(g.measured_by, AgentId(victim));
  }
  int64_t measured = 0, delivered = 0;
  for (const AgentSummary& a : out.agents) measured += a.report.measured;
  for (const mission::GoalRecord& g : out.result.goals) delivered += g.state == mission::GoalState::kDelivered;
  EXPECT_EQ(measured, delivered);  // nothing measured was lost, nothing counted twice
}

}  // namespace
}  // namespace agent
}  // namespace gather
