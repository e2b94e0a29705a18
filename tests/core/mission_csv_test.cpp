// mission/mission_csv: the three CSV files every runner writes, and the
// result of a run computed from its goals.
#include "gather_core/mission/mission_csv.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace mission {
namespace {

std::size_t fields(const std::string& line) {
  return static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// Goal 0 (cycle 0) measured by worker 3 at 4.5 s, picked up by collector 0 at
// 6 s, delivered by it at 9.25 s; goal 1 (cycle 1) never measured: expired at
// the next request (20 s). Requests every 10 s, two cycles.
std::vector<GoalRecord> two_goals() {
  GoalRecord a;
  a.id = GoalId(0), a.cycle = 0, a.point = Point2{1.0, 2.0}, a.segment = SegmentId(3), a.worker = AgentId(3);
  a.requested_at = 0.0, a.deadline = 10.0;
  a.measured_at = 4.5, a.measured_by = AgentId(3), a.picked_up_at = 6.0, a.picked_up_by = AgentId(0);
  a.delivered_at = 9.25, a.delivered_by = AgentId(0), a.state = GoalState::kDelivered;
  GoalRecord b;
  b.id = GoalId(1), b.cycle = 1, b.point = Point2{-1.5, 0.25}, b.segment = SegmentId(2), b.worker = AgentId(2);
  b.requested_at = 10.0, b.deadline = 20.0, b.expired_at = 20.0, b.state = GoalState::kExpired;
  return {a, b};
}

const RunLabel kRun{"pap", 1, 4, 7, 2, 8.0, 1.5, 12.0};

// The goal records a run keeps are bounded (docs/input_limits.md): at the
// budget it runs, one more is refused in one line naming what to lower.
TEST(MissionCsvTest, GoalRecordsOverTheBudgetAreRefusedUpFront) {
  EXPECT_NO_THROW(mission::check_goal_budget(40, 10, 1, "s.yaml"));
  EXPECT_NO_THROW(mission::check_goal_budget(mission::kMaxGoalRecords, 1, 1, "s.yaml"));
  try {
    mission::check_goal_budget(5000, 10000, 1000, "s.yaml");  // every maximum at once
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.yaml: mission.goals_per_request x cycles x runs = 5000 x 10000 x 1000 = "
                                          "50000000000 goal records, over the budget",
                                          0),
              0u)
        << e.what();
  }
  EXPECT_THROW(mission::check_goal_budget(mission::kMaxGoalRecords + 1, 1, 1, "s.yaml"), Error);
}

TEST(MissionCsvTest, AGoalRowByHandAndEveryRowHasItsHeadersFields) {
  std::string goals;
  append_goal_rows(goals, kRun, two_goals());
  EXPECT_EQ(first_line(goals), "pap,1,7,0,0,1.000,2.000,3,3,0.000,4.500,3,6.000,0,9.250,0,delivered,-1.000");
  EXPECT_EQ(fields(first_line(goals)), fields(first_line(kGoalsCsvHeader)));
  EXPECT_EQ(std::count(goals.begin(), goals.end(), '\n'), 2);

  const MissionResult r = mission_result(two_goals(), 2, 10.0, 5.0, AreaWeights{});
  std::string cycles, summary;
  append_cycle_rows(cycles, kRun, r.cycles);
  append_summary_row(summary, kRun, r);
  EXPECT_EQ(std::count(cycles.begin(), cycles.end(), '\n'), 2);
  EXPECT_EQ(fields(first_line(cycles)), fields(first_line(kCyclesCsvHeader)));
  EXPECT_EQ(fields(first_line(summary)), fields(first_line(kSummaryCsvHeader)));
  EXPECT_EQ(summary.rfind("pap,1,4,7,2,10.000,20.000,5.00,", 0), 0u) << summary;
}

TEST(MissionCsvTest, TheResultCountsEveryGoalOnce) {
  const MissionResult r = mission_result(two_goals(), 2, 10.0, 5.0, AreaWeights{});
  EXPECT_EQ(r.delivered, 1);
  EXPECT_EQ(r.expired, 1);
  EXPECT_EQ(r.dropped + r.lost_with_agent, 0);
  EXPECT_DOUBLE_EQ(r.refresh_mean_s, 9.25);
  EXPECT_DOUBLE_EQ(r.refresh_max_s, 9.25);
  EXPECT_DOUBLE_EQ(r.goals_per_cycle, 0.5);
  EXPECT_DOUBLE_EQ(r.mission_s, 20.0);
  EXPECT_DOUBLE_EQ(r.end_s, 20.0);  // the expiry
  ASSERT_EQ(r.cycles.size(), 2u);
  EXPECT_EQ(r.cycles[0].delivered, 1);
  EXPECT_EQ(r.cycles[1].expired, 1);
}

TEST(MissionCsvTest, ABrokenHistoryIsRefused) {
  std::vector<GoalRecord> goals = two_goals();
  goals[0].measured_at = -1.0;  // delivered without being measured
  EXPECT_ANY_THROW(mission_result(goals, 2, 10.0, 5.0, AreaWeights{}));
}

}  // namespace
}  // namespace mission
}  // namespace gather
