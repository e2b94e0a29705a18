#pragma once
// A planned configuration as what executes it: the plan file (plan.yaml) and
// the mission plan the simulator and the agents run.
#include <string>

#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// Agents 0..N_c-1 are the collectors, N_c..N-1 the workers of segments 1..N_w.
PlanFile make_plan_file(const PlanContext& ctx, const ConfigurationPlan& cfg, const std::string& labels_png,
                        unsigned seed);

}  // namespace plan

namespace mission {

// The plan of `cfg` as `gather plan` would write it (no file is written).
MissionPlan mission_plan(const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg, unsigned seed = 1);

}  // namespace mission
}  // namespace gather
