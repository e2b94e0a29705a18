#pragma once
// maps/office planned once per test binary, for the runtime's tests: pap:4
// with the collector groups as grown (all four collectors serve workers) and
// bap:0, and the mission parameters of its scenario.
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

}  // namespace testing_support
}  // namespace gather
