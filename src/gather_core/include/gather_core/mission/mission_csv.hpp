#pragma once
// A mission run as the three CSV files every runner writes in one schema
// (`gather sim`, `gather run`, a multi-process mission): goals.csv (one row
// per goal), cycles.csv (one row per request), summary.csv (one row per run).
// docs/simulator.md describes the columns.
#include <string>
#include <vector>

#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace mission {

// What identifies one run in the CSV rows.
struct RunLabel {
  std::string method;
  int collectors = 0;
  int workers = 0;
  unsigned seed = 1;
  int cycles = 0;
  double est_refresh_s = 0.0, est_goals = 0.0, est_interval_s = 0.0;
};

extern const char* const kGoalsCsvHeader;
extern const char* const kCyclesCsvHeader;
extern const char* const kSummaryCsvHeader;

void append_goal_rows(std::string& out, const RunLabel& run, const std::vector<GoalRecord>& goals);
void append_cycle_rows(std::string& out, const RunLabel& run, const std::vector<CycleStats>& cycles);
void append_summary_row(std::string& out, const RunLabel& run, const MissionResult& result);

// The result of a run from its goals: the accounting (mission::account,
// which throws on a broken history) and the metrics. `wall_ms` [ms] is what
// the run took; `areas` those of the refresh interval (area_weights of the
// world with plan.yaml's area_tile_m).
MissionResult mission_result(std::vector<GoalRecord> goals, int cycles, double period, double wall_ms,
                             const AreaWeights& areas);

}  // namespace mission
}  // namespace gather
