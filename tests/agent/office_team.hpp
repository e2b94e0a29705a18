#pragma once
// maps/office planned once per test binary, for the runtime's tests: pap:4
// with the collector groups as grown (all four collectors serve workers) and
// bap:0, and the mission parameters of its scenario.
#include <algorithm>
#include <string>

#include "gather_agent/roles/role.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace testing_support {

struct Office {
  static Office& get() {
    static Office o;
    return o;
  }
  Scenario map = load_scenario(std::string(GATHER_REPO_DIR) + "/maps/office.scenario.yaml");
  Scenario scenario = on_planning_grid(map, planning_factor(map));
  plan::PlanContext ctx{scenario};
  mission::MissionPlan pap4 =
      mission::mission_plan(ctx, plan::plan_configuration(ctx, partition::Method::kPap, 4, plan::grown_groups()));
  mission::MissionPlan bap0 = mission::mission_plan(ctx, plan::plan_configuration(ctx, partition::Method::kBap, 0));
};

inline agent::MissionParams office_params(int cycles, unsigned seed) {
  agent::MissionParams p;
  p.cycles = cycles, p.seed = seed, p.goals_per_request = Office::get().scenario.mission.goals_per_request;
  return p;
}

// The first worker of `plan` (of the OC when `of_oc`, else of a collector).
inline AgentId a_worker(const mission::MissionPlan& plan, bool of_oc) {
  for (const plan::AgentAssignment& a : plan.file.agents)
    if (!a.collector && !a.delivers_to.valid() == of_oc) return a.id;
  return AgentId();
}

// The collector of `plan` with the most workers.
inline CollectorId busiest_collector(const mission::MissionPlan& plan) {
  PerCollector<int> n(plan.file.collectors, 0);
  for (const plan::AgentAssignment& a : plan.file.agents)
    if (!a.collector && a.delivers_to.valid()) ++n[a.delivers_to];
  return CollectorId::at_index(static_cast<std::size_t>(std::max_element(n.begin(), n.end()) - n.begin()));
}

}  // namespace testing_support
}  // namespace gather
