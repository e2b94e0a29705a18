#include "gather_core/plan/plan_export.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"
#include "gather_core/partition/partition.hpp"

namespace gather {
namespace plan {

PlanFile make_plan_file(const PlanContext& ctx, const ConfigurationPlan& cfg, const std::string& labels_png,
                        unsigned seed) {
  PlanFile p;
  p.scenario = std::filesystem::weakly_canonical(ctx.scenario.path).string();
  p.method = partition::method_name(cfg.method);
  p.collectors = cfg.collectors;
  p.workers = cfg.workers;
  p.seed = seed;
  p.labels_png = labels_png;
  const double map_res = ctx.scenario.map_meta.resolution;  // 0 for scenarios built in code
  p.grid_factor =
      map_res > 0 ? std::max(1, static_cast<int>(std::lround(ctx.scenario.grid.resolution() / map_res))) : 1;
  p.cycle_period_s = ctx.cycle_period;
  p.area_tile_m = ctx.area_tile;
  p.est_refresh_s = cfg.estimates.refresh_s;
  p.est_goals = cfg.estimates.goals;
  p.est_interval_s = cfg.estimates.interval_s;
  p.utility = cfg.utility;
  // Collector k is agent k; the worker of segment k is agent N_c + k - 1.
  for (CollectorId c : ids<CollectorId>(cfg.collectors))
    p.agents.push_back(AgentAssignment{AgentId(c.value()), true, SegmentId(), c});
  for (SegmentId k : segment_ids(cfg.workers))
    p.agents.push_back(
        AgentAssignment{AgentId(cfg.collectors + static_cast<int>(k.index())), false, k, cfg.collector_of_segment[k]});
  p.routes = cfg.routes;
  p.workers_est = cfg.estimates.workers;
  return p;
}

void write_sweep_report(const std::string& path, const SweepResult& sweep) {
  std::ofstream out(path);
  out << "method,collectors,active_collectors,workers,oc_workers,est_refresh_s,est_interval_s,est_goals,utility,plan_"
         "ms,partition_ms,graph_ms,groups_ms,"
         "routes_ms,estimate_ms,associate_ms\n";
  char line[512];
  for (const auto& c : sweep.configs) {
    const int oc_workers =
        static_cast<int>(std::count(c.collector_of_segment.begin(), c.collector_of_segment.end(), CollectorId()));
    const int active = static_cast<int>(
        std::count_if(c.routes.begin(), c.routes.end(), [](const CollectorRoute& r) { return !r.segments.empty(); }));
    std::snprintf(line, sizeof line, "%s,%d,%d,%d,%d,%.3f,%.3f,%.3f,%.4f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f\n",
                  partition::method_name(c.method), c.collectors, active, c.workers, oc_workers, c.estimates.refresh_s,
                  c.estimates.interval_s, c.estimates.goals, c.utility, c.times.total(), c.times.partition_ms,
                  c.times.graph_ms, c.times.groups_ms, c.times.routes_ms, c.times.estimate_ms, c.times.associate_ms);
    out << line;
  }
  if (!out) throw Error(path, "cannot write report");
}

std::string plan_scenario(const std::string& scenario_path, const std::string& dir, int threads,
                          const PlanFigureWriter& figures) {
  const Scenario map_scenario = load_scenario(scenario_path);
  const Scenario s = on_planning_grid(map_scenario, planning_factor(map_scenario));
  PlannerOptions opt;
  opt.seed = s.mission.seed;
  opt.threads = threads;
  const PlanContext ctx(s, opt);
  const SweepResult sweep = plan::sweep(ctx, opt);
  const ConfigurationPlan& best = sweep.configs[static_cast<std::size_t>(sweep.best)];
  write_plan_directory(dir, ctx, best, opt.seed, figures);
  write_sweep_report(dir + "/report.csv", sweep);
  char line[256];
  std::snprintf(line, sizeof line,
                "%s with %d collectors and %d workers (U = %.3f, est. refresh %.1f s, %.2f goals per cycle of %.1f s)",
                partition::method_name(best.method), best.collectors, best.workers, best.utility,
                best.estimates.refresh_s, best.estimates.goals, ctx.cycle_period);
  return line;
}

void write_plan_directory(const std::string& dir, const PlanContext& ctx, const ConfigurationPlan& cfg, unsigned seed,
                          const PlanFigureWriter& figures) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(dir, "cannot create the plan directory (" + ec.message() + ")");
  partition::write_label_png(dir + "/labels.png", cfg.partition);
  write_plan_file(dir + "/plan.yaml", make_plan_file(ctx, cfg, "labels.png", seed));
  if (figures) figures(dir, ctx, cfg);
}

}  // namespace plan

namespace mission {

MissionPlan mission_plan(const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg, unsigned seed) {
  MissionPlan m;
  m.file = plan::make_plan_file(ctx, cfg, "", seed);
  m.labels = cfg.partition.labels;
  return m;
}

}  // namespace mission
}  // namespace gather
