#include "gather_core/plan/plan_export.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

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
  p.grid_factor = map_res > 0 ? std::max(1, static_cast<int>(std::lround(ctx.scenario.grid.resolution() / map_res))) : 1;
  p.cycle_period_s = ctx.cycle_period;
  p.est_refresh_s = cfg.estimates.refresh_s;
  p.est_goals = cfg.estimates.goals;
  p.utility = cfg.utility;
  for (int c = 0; c < cfg.collectors; ++c) p.agents.push_back(AgentAssignment{c, true, 0, c});
  for (int k = 1; k <= cfg.workers; ++k)
    p.agents.push_back(AgentAssignment{cfg.collectors + k - 1, false, k, cfg.collector_of_segment[static_cast<std::size_t>(k - 1)]});
  p.routes = cfg.routes;
  p.workers_est = cfg.estimates.workers;
  return p;
}

}  // namespace plan

namespace mission {

MissionPlan mission_plan(const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg, unsigned seed) {
  MissionPlan m;
  m.file = plan::make_plan_file(ctx, cfg, "", seed);
  m.width = cfg.partition.width;
  m.height = cfg.partition.height;
  m.labels = cfg.partition.labels;
  return m;
}

}  // namespace mission
}  // namespace gather
