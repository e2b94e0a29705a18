#pragma once
// What the mission simulator executes: a plan (roles, segments, collector
// routes, cycle period, estimates) and the segment label of every cell. Built
// in memory from a planned configuration, or read from a `gather plan` output
// directory (plan.yaml + the 16-bit labels.png beside it).
#include <cstdint>
#include <string>
#include <vector>

#include "gather_core/plan/plan_file.hpp"

namespace gather {
namespace mission {

struct MissionPlan {
  std::string source;           // the plan.yaml it was read from ("" for a plan built in memory): errors name it
  plan::PlanFile file;          // roles, routes, cycle_period_s, estimates
  int width = 0, height = 0;    // of the label image [cells]
  std::vector<int32_t> labels;  // row-major (row 0 = bottom), 0 = no segment, k = segment k
};

// Reads `plan_yaml` (or PLAN_DIR/plan.yaml when given a directory) and the
// labels image it names (16-bit PNG, image row 0 = top of the map). Throws
// gather::Error naming the file on I/O or format errors.
MissionPlan load_mission_plan(const std::string& plan_path);

// The structure executing a plan relies on, for a team of `team` agents:
// ids 0..team-1 once each, collector indices 0..N_c-1 once each with one
// route each, one worker per segment 1..N_w delivering to the OC or to a
// collector whose route has a meeting area for its segment, finite
// waypoints, cycle_period_s > 0. Throws gather::Error naming plan.source
// ("plan" for a plan built in memory) and the agent or route at fault.
void check_plan(const MissionPlan& plan, int team);

}  // namespace mission
}  // namespace gather
