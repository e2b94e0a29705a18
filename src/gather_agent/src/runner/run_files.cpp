#include "gather_agent/runner/run_files.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {

const char* const kAgentsCsvHeader =
    "method,collectors,seed,agent,role,measured,expired,skipped,dropped,carried,delivered,sent,received,gated,lost,"
    "bad,overflow\n";

LoadedPlan load_plan(const std::string& plan_dir) {
  namespace fs = std::filesystem;
  if (!fs::exists(plan_dir)) throw Error(plan_dir, "no such plan directory");
  LoadedPlan l;
  l.dir = plan_dir;
  l.plan = mission::load_mission_plan(plan_dir);
  const fs::path yaml = fs::is_directory(plan_dir) ? fs::path(plan_dir) / "plan.yaml" : fs::path(plan_dir);
  if (!fs::exists(l.plan.file.scenario))
    throw Error(yaml.string(), "names scenario " + l.plan.file.scenario + ", which does not exist");
  l.scenario = on_planning_grid(load_scenario(l.plan.file.scenario), l.plan.file.grid_factor);
  const OccupancyGrid& g = l.scenario.grid;
  if (l.plan.width != g.width() || l.plan.height != g.height())
    throw Error(yaml.string(), "its labels are " + std::to_string(l.plan.width) + "x" + std::to_string(l.plan.height) +
                                   " cells, scenario " + l.plan.file.scenario + " on the plan's grid is " +
                                   std::to_string(g.width()) + "x" + std::to_string(g.height()));
  if (static_cast<int>(l.plan.file.agents.size()) != l.scenario.team.agents)
    throw Error(yaml.string(), "plans " + std::to_string(l.plan.file.agents.size()) + " agents, scenario " +
                                   l.plan.file.scenario + " has a team of " + std::to_string(l.scenario.team.agents));
  return l;
}

MissionParams mission_params(const Scenario& s) {
  MissionParams p;
  p.cycles = s.mission.cycles;
  p.seed = s.mission.seed;
  p.goals_per_request = s.mission.goals_per_request;
  return p;
}

void append_agent_rows(std::string& out, const plan::PlanFile& plan, unsigned seed, const std::vector<AgentSummary>& agents) {
  char line[512];
  for (const AgentSummary& a : agents) {
    std::snprintf(line, sizeof line, "%s,%d,%u,%d,%s,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld\n",
                  plan.method.c_str(), plan.collectors, seed, a.id, role_kind_name(a.role),
                  static_cast<long long>(a.report.measured), static_cast<long long>(a.report.expired),
                  static_cast<long long>(a.report.skipped), static_cast<long long>(a.report.dropped),
                  static_cast<long long>(a.carried), static_cast<long long>(a.delivered),
                  static_cast<long long>(a.link.sent), static_cast<long long>(a.link.received),
                  static_cast<long long>(a.link.gated), static_cast<long long>(a.link.lost),
                  static_cast<long long>(a.link.bad), static_cast<long long>(a.link.overflow));
    out += line;
  }
}

void RunFiles::add(const plan::PlanFile& plan, const MissionParams& params, const RunOutcome& run) {
  const mission::RunLabel label{plan.method, plan.collectors, plan.workers, params.seed, params.cycles,
                                plan.est_refresh_s, plan.est_goals};
  mission::append_goal_rows(goals_, label, run.result.goals);
  mission::append_cycle_rows(cycles_, label, run.result.cycles);
  mission::append_summary_row(summary_, label, run.result);
  append_agent_rows(agents_, plan, params.seed, run.agents);
}

void RunFiles::write(const std::string& dir) const {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  auto put = [&](const std::string& name, const char* header, const std::string& rows) {
    std::ofstream f(dir + "/" + name);
    f << header << rows;
    if (!f) throw Error(dir + "/" + name, "cannot write");
  };
  put("goals.csv", mission::kGoalsCsvHeader, goals_);
  put("cycles.csv", mission::kCyclesCsvHeader, cycles_);
  put("summary.csv", mission::kSummaryCsvHeader, summary_);
  put("agents.csv", kAgentsCsvHeader, agents_);
}

}  // namespace agent
}  // namespace gather
