#include "gather_agent/runner/run_files.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <yaml-cpp/yaml.h>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {

const char* const kAgentsCsvHeader =
    "method,collectors,seed,agent,role,measured,expired,skipped,dropped,carried,delivered,sent,received,gated,lost,"
    "bad,overflow,rejected_unsigned,rejected_unknown_key,rejected_bad_mac,rejected_replayed,rejected_wrong_sender,"
    "legs,legs_late,late_median_s,late_max_s,nav_failures,unreachable,contacts,robot_faults,loops,loop_late_median_s,"
    "loop_late_max_s,refused_revoked\n";

LoadedPlan load_plan(const std::string& plan_dir) {
  namespace fs = std::filesystem;
  if (plan_dir.empty()) throw Error("", "no plan directory named: the path is empty");
  if (!fs::exists(plan_dir)) throw Error(plan_dir, "no such plan directory");
  LoadedPlan l;
  l.dir = plan_dir;
  l.plan = mission::load_mission_plan(plan_dir);
  const fs::path yaml = fs::is_directory(plan_dir) ? fs::path(plan_dir) / "plan.yaml" : fs::path(plan_dir);
  if (!fs::exists(l.plan.file.scenario))
    throw Error(yaml.string(), "names scenario " + l.plan.file.scenario + ", which does not exist");
  l.scenario = on_planning_grid(load_scenario(l.plan.file.scenario), l.plan.file.grid_factor);
  const OccupancyGrid& g = l.scenario.grid;
  if (!l.plan.labels.frame().same_size(g.frame()))
    throw Error(yaml.string(), "its labels are " + l.plan.labels.frame().size_text() + " cells, scenario " +
                                   l.plan.file.scenario + " on the plan's grid is " + g.frame().size_text());
  mission::check_plan(l.plan, l.scenario.team.agents, g);
  l.plan.labels.reframe(g.frame());
  return l;
}

MissionParams mission_params(const Scenario& s) {
  MissionParams p;
  p.cycles = s.mission.cycles;
  p.seed = s.mission.seed;
  p.goals_per_request = s.mission.goals_per_request;
  return p;
}

void append_agent_rows(std::string& out, const plan::PlanFile& plan, unsigned seed,
                       const std::vector<AgentSummary>& agents) {
  char line[640];
  for (const AgentSummary& a : agents) {
    std::snprintf(
        line, sizeof line,
        "%s,%d,%u,%d,%s,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,%lld,"
        "%.1f,%.1f,%lld,%lld,%d,%lld,%lld,%.1f,%.1f,%lld\n",
        plan.method.c_str(), plan.collectors, seed, a.id, role_kind_name(a.role),
        static_cast<long long>(a.report.measured), static_cast<long long>(a.report.expired),
        static_cast<long long>(a.report.skipped), static_cast<long long>(a.report.dropped),
        static_cast<long long>(a.carried), static_cast<long long>(a.delivered), static_cast<long long>(a.link.sent),
        static_cast<long long>(a.link.received), static_cast<long long>(a.link.gated),
        static_cast<long long>(a.link.lost), static_cast<long long>(a.link.bad),
        static_cast<long long>(a.link.overflow), static_cast<long long>(a.auth.unsigned_msgs),
        static_cast<long long>(a.auth.unknown_key), static_cast<long long>(a.auth.bad_mac),
        static_cast<long long>(a.auth.replayed), static_cast<long long>(a.auth.wrong_sender),
        static_cast<long long>(a.report.legs), static_cast<long long>(a.report.legs_late), a.report.late_median_s,
        a.report.late_max_s, static_cast<long long>(a.report.nav_failures),
        static_cast<long long>(a.report.unreachable), a.contacts, static_cast<long long>(a.robot.faults),
        static_cast<long long>(a.report.loops), a.report.loop_late_median_s, a.report.loop_late_max_s,
        static_cast<long long>(a.report.refused_revoked));
    out += line;
  }
}

namespace {

// Messages dropped before decoding, by reason (docs/security.md).
void emit_rejected(YAML::Emitter& y, const AuthCounters& a) {
  y << YAML::Flow << YAML::BeginMap << YAML::Key << "unsigned" << YAML::Value << a.unsigned_msgs << YAML::Key
    << "unknown_key" << YAML::Value << a.unknown_key << YAML::Key << "bad_mac" << YAML::Value << a.bad_mac << YAML::Key
    << "replayed" << YAML::Value << a.replayed << YAML::Key << "wrong_sender" << YAML::Value << a.wrong_sender
    << YAML::EndMap;
}

}  // namespace

void write_mission_yaml(const std::string& path, const LoadedPlan& plan, const MissionParams& params,
                        const RunSettings& settings, const RunOutcome& run) {
  const plan::PlanFile& pf = plan.plan.file;
  int64_t requested = 0, delivered = 0, expired = 0, dropped = 0, lost = 0;
  for (const mission::GoalRecord& g : run.result.goals) {
    ++requested;
    delivered += g.state == mission::GoalState::kDelivered;
    expired += g.state == mission::GoalState::kExpired;
    dropped += g.state == mission::GoalState::kDropped;
    lost += g.state == mission::GoalState::kLostWithAgent;
  }
  YAML::Emitter y;
  y.SetDoublePrecision(6);
  y << YAML::BeginMap;
  y << YAML::Key << "status" << YAML::Value << (run.completed ? "ok" : "incomplete");
  if (!run.completed) y << YAML::Key << "failure" << YAML::Value << run.failure;
  y << YAML::Key << "scenario" << YAML::Value << pf.scenario;
  y << YAML::Key << "plan" << YAML::Value << std::filesystem::weakly_canonical(plan.dir).string();
  y << YAML::Key << "map" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "width" << YAML::Value
    << plan.scenario.grid.width() << YAML::Key << "height" << YAML::Value << plan.scenario.grid.height() << YAML::Key
    << "resolution" << YAML::Value << plan.scenario.grid.resolution() << YAML::EndMap;
  y << YAML::Key << "oc" << YAML::Value << YAML::Flow << YAML::BeginSeq << plan.scenario.oc.x << plan.scenario.oc.y
    << YAML::EndSeq;
  y << YAML::Key << "configuration" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "method"
    << YAML::Value << pf.method << YAML::Key << "collectors" << YAML::Value << pf.collectors << YAML::Key << "workers"
    << YAML::Value << pf.workers << YAML::EndMap;
  y << YAML::Key << "run" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "transport" << YAML::Value
    << settings.transport << YAML::Key << "cycles" << YAML::Value << params.cycles << YAML::Key << "seed" << YAML::Value
    << params.seed << YAML::Key << "period_s" << YAML::Value << pf.cycle_period_s << YAML::Key << "tick_s"
    << YAML::Value << settings.tick << YAML::Key << "rate" << YAML::Value << settings.rate << YAML::Key << "loss"
    << YAML::Value << settings.loss << YAML::Key << "ticks" << YAML::Value << run.ticks << YAML::Key << "end_s"
    << YAML::Value << run.end_s << YAML::Key << "wall_s" << YAML::Value << run.wall_ms / 1000.0 << YAML::Key
    << "speedup" << YAML::Value << (run.wall_ms > 0 ? run.end_s * 1000.0 / run.wall_ms : 0.0) << YAML::Key << "messages"
    << YAML::Value << run.messages << YAML::EndMap;
  y << YAML::Key << "goals" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "requested" << YAML::Value
    << requested << YAML::Key << "delivered" << YAML::Value << delivered << YAML::Key << "expired" << YAML::Value
    << expired << YAML::Key << "dropped" << YAML::Value << dropped << YAML::Key << "lost_with_agent" << YAML::Value
    << lost << YAML::Key << "per_cycle" << YAML::Value << run.result.goals_per_cycle << YAML::Key << "est_per_cycle"
    << YAML::Value << pf.est_goals << YAML::EndMap;
  y << YAML::Key << "refresh" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "mean_s" << YAML::Value
    << run.result.refresh_mean_s << YAML::Key << "max_s" << YAML::Value << run.result.refresh_max_s << YAML::Key
    << "est_s" << YAML::Value << pf.est_refresh_s << YAML::EndMap;
  y << YAML::Key << "oc" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "sent" << YAML::Value
    << run.oc_link.sent << YAML::Key << "received" << YAML::Value << run.oc_link.received << YAML::Key << "gated"
    << YAML::Value << run.oc_link.gated << YAML::Key << "lost" << YAML::Value << run.oc_link.lost << YAML::Key << "bad"
    << YAML::Value << run.oc_link.bad << YAML::Key << "invalid_items" << YAML::Value << run.invalid_items << YAML::Key
    << "duplicate_items" << YAML::Value << run.duplicate_items << YAML::Key << "rejected" << YAML::Value;
  emit_rejected(y, run.oc_auth);
  y << YAML::EndMap;
  y << YAML::Key << "faults" << YAML::Value << YAML::BeginSeq;
  std::map<int, std::pair<double, double>> faults;  // agent -> (killed_at, declared_dead_at), -1: not
  for (const Kill& k : run.kills) faults[k.agent] = {k.at, -1.0};
  for (const auto& [a, at] : run.declared_dead) {
    auto it = faults.emplace(a, std::make_pair(-1.0, at)).first;
    it->second.second = at;
  }
  for (const auto& [a, t] : faults) {
    const Revocation* revoked = revocation_of(run.revoked, a);
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "agent" << YAML::Value << a << YAML::Key << "killed_at"
      << YAML::Value << t.first << YAML::Key << "declared_dead_at" << YAML::Value << t.second << YAML::Key
      << "revoked_at" << YAML::Value << (revoked ? revoked->at : -1.0) << YAML::EndMap;
  }
  y << YAML::EndSeq;
  y << YAML::Key << "agents" << YAML::Value << YAML::BeginSeq;
  for (const AgentSummary& a : run.agents) {
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << a.id << YAML::Key << "role" << YAML::Value
      << role_kind_name(a.role) << YAML::Key << "measured" << YAML::Value << a.report.measured << YAML::Key << "carried"
      << YAML::Value << a.carried << YAML::Key << "delivered" << YAML::Value << a.delivered << YAML::Key << "expired"
      << YAML::Value << a.report.expired << YAML::Key << "skipped" << YAML::Value << a.report.skipped << YAML::Key
      << "dropped" << YAML::Value << a.report.dropped << YAML::Key << "sent" << YAML::Value << a.link.sent << YAML::Key
      << "received" << YAML::Value << a.link.received << YAML::Key << "gated" << YAML::Value << a.link.gated
      << YAML::Key << "lost" << YAML::Value << a.link.lost << YAML::Key << "bad" << YAML::Value << a.link.bad
      << YAML::Key << "rejected" << YAML::Value;
    emit_rejected(y, a.auth);
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  std::ofstream out(path);
  out << y.c_str() << "\n";
  if (!out) throw Error(path, "cannot write");
}

void RunFiles::add(const plan::PlanFile& plan, const MissionParams& params, const RunOutcome& run) {
  const mission::RunLabel label{plan.method,   plan.collectors,    plan.workers,   params.seed,
                                params.cycles, plan.est_refresh_s, plan.est_goals, plan.est_interval_s};
  mission::append_goal_rows(goals_, label, run.result.goals);
  mission::append_cycle_rows(cycles_, label, run.result.cycles);
  mission::append_summary_row(summary_, label, run.result);
  append_agent_rows(agents_, plan, params.seed, run.agents);
  append_fault_rows(faults_, plan, params.seed, run);
  char line[256];
  const AuthCounters& a = run.oc_auth;
  std::snprintf(line, sizeof line, "%s,%d,%u,%lld,%lld,%lld,%lld,%lld\n", plan.method.c_str(), plan.collectors,
                params.seed, static_cast<long long>(a.unsigned_msgs), static_cast<long long>(a.unknown_key),
                static_cast<long long>(a.bad_mac), static_cast<long long>(a.replayed),
                static_cast<long long>(a.wrong_sender));
  oc_rejected_ += line;
}

const char* const kOcRejectedCsvHeader =
    "method,collectors,seed,rejected_unsigned,rejected_unknown_key,rejected_bad_mac,rejected_replayed,"
    "rejected_wrong_sender\n";

const char* const kFaultsCsvHeader =
    "method,collectors,seed,agent,role,killed_at,declared_at,restarted,recovered,revoked_at,oc_refused,oc_discarded\n";

void append_fault_rows(std::string& out, const plan::PlanFile& plan, unsigned seed, const RunOutcome& run) {
  std::map<int, std::pair<double, double>> rows;  // agent -> (killed_at, declared_at), -1: not
  for (const Kill& k : run.kills) rows.emplace(k.agent, std::make_pair(k.at, -1.0));
  for (const Kill& k : run.restarts) rows.emplace(k.agent, std::make_pair(k.at, -1.0));
  for (const auto& [a, at] : run.declared_dead) {
    auto it = rows.emplace(a, std::make_pair(-1.0, at)).first;
    it->second.second = at;
  }
  char line[320];
  for (const auto& [a, t] : rows) {
    const plan::AgentAssignment& x = plan.agents[AgentId(a)];
    bool restarted = false;
    for (const Kill& k : run.restarts) restarted = restarted || k.agent == a;
    const Revocation* found = revocation_of(run.revoked, a);
    const Revocation revoked = found ? *found : Revocation{a, -1.0, 0, 0};
    std::snprintf(line, sizeof line, "%s,%d,%u,%d,%s,%.3f,%.3f,%d,%lld,%.3f,%lld,%lld\n", plan.method.c_str(),
                  plan.collectors, seed, a,
                  x.collector              ? "collector"
                  : !x.delivers_to.valid() ? "oc_worker"
                                           : "collector_worker",
                  t.first, t.second, restarted ? 1 : 0, static_cast<long long>(run.recovered), revoked.at,
                  static_cast<long long>(revoked.oc_refused), static_cast<long long>(revoked.oc_discarded));
    out += line;
  }
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
  put("faults.csv", kFaultsCsvHeader, faults_);
  put("oc_rejected.csv", kOcRejectedCsvHeader, oc_rejected_);
}

}  // namespace agent
}  // namespace gather
