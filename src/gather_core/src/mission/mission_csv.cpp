#include "gather_core/mission/mission_csv.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <tuple>

namespace gather {
namespace mission {

const char* const kGoalsCsvHeader =
    "method,collectors,seed,goal,cycle,x,y,segment,worker,requested_at,measured_at,measured_by,picked_up_at,"
    "picked_up_by,delivered_at,delivered_by,state,lost_at\n";
const char* const kCyclesCsvHeader =
    "method,collectors,seed,cycle,requested_at,requested,delivered,expired,refresh_mean_s,refresh_max_s,"
    "total_requested,total_delivered,total_carried,total_pending,total_expired,dropped,total_dropped,lost_with_agent,"
    "total_lost_with_agent,unreachable,total_unreachable\n";
const char* const kSummaryCsvHeader =
    "method,collectors,workers,seed,cycles,period_s,mission_s,wall_ms,speedup,refresh_mean_s,refresh_max_s,"
    "goals_per_cycle,est_refresh_s,est_goals,interval_mean_s,interval_max_s,est_interval_s,delivered,expired,"
    "dropped_overflow,lost_with_agent,unreachable\n";

void append_goal_rows(std::string& out, const RunLabel& run, const std::vector<GoalRecord>& goals) {
  char line[640];
  for (const GoalRecord& g : goals) {
    std::snprintf(line, sizeof line, "%s,%d,%u,%d,%d,%.3f,%.3f,%d,%d,%.3f,%.3f,%d,%.3f,%d,%.3f,%d,%s,%.3f\n",
                  run.method.c_str(), run.collectors, run.seed, g.id.value(), g.cycle, g.point.x, g.point.y,
                  g.segment.label(), g.worker.value(), g.requested_at, g.measured_at, g.measured_by.value(),
                  g.picked_up_at, g.picked_up_by.value(), g.delivered_at, g.delivered_by.value(),
                  goal_state_name(g.state), g.lost_at);
    out += line;
  }
}

void append_cycle_rows(std::string& out, const RunLabel& run, const std::vector<CycleStats>& cycles) {
  char line[640];
  for (const CycleStats& c : cycles) {
    std::snprintf(line, sizeof line, "%s,%d,%u,%d,%.3f,%d,%d,%d,%.3f,%.3f,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d\n",
                  run.method.c_str(), run.collectors, run.seed, c.cycle, c.requested_at, c.requested, c.delivered,
                  c.expired, c.refresh_mean_s, c.refresh_max_s, c.total_requested, c.total_delivered, c.total_carried,
                  c.total_pending, c.total_expired, c.dropped, c.total_dropped, c.lost, c.total_lost, c.unreachable,
                  c.total_unreachable);
    out += line;
  }
}

void append_summary_row(std::string& out, const RunLabel& run, const MissionResult& r) {
  char line[640];
  std::snprintf(line, sizeof line,
                "%s,%d,%d,%u,%d,%.3f,%.3f,%.2f,%.1f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d,%d,%d,%d\n",
                run.method.c_str(), run.collectors, run.workers, run.seed, run.cycles, r.period_s, r.mission_s,
                r.wall_ms, r.speedup(), r.refresh_mean_s, r.refresh_max_s, r.goals_per_cycle, run.est_refresh_s,
                run.est_goals, r.interval_mean_s, r.interval_max_s, run.est_interval_s, r.delivered, r.expired,
                r.dropped, r.lost_with_agent, r.unreachable);
  out += line;
}

MissionResult mission_result(std::vector<GoalRecord> goals, int cycles, double period, double wall_ms,
                             const AreaWeights& areas) {
  MissionResult res;
  res.cycles = account(goals, cycles, period);
  res.period_s = period;
  res.mission_s = cycles * period;
  int delivered = 0;
  double sum = 0.0;
  for (const GoalRecord& g : goals) {
    res.end_s = std::max({res.end_s, g.delivered_at, g.expired_at, g.dropped_at, g.lost_at, g.unreachable_at});
    res.expired += g.state == GoalState::kExpired;
    res.dropped += g.state == GoalState::kDropped;
    res.lost_with_agent += g.state == GoalState::kLostWithAgent;
    res.unreachable += g.state == GoalState::kUnreachable;
    if (g.delivered_at < 0) continue;
    const double r = g.delivered_at - g.requested_at;
    ++delivered, sum += r, res.refresh_max_s = std::max(res.refresh_max_s, r);
  }
  res.refresh_mean_s = delivered > 0 ? sum / delivered : 0.0;
  res.delivered = delivered;
  res.goals_per_cycle = static_cast<double>(delivered) / cycles;
  std::tie(res.interval_mean_s, res.interval_max_s) = interval_stats(goals, cycles, period, areas);
  res.goals = std::move(goals);
  res.wall_ms = wall_ms;
  return res;
}

}  // namespace mission
}  // namespace gather
