#pragma once
// What the mission simulator executes: a plan (roles, segments, collector
// routes, cycle period, estimates) and the segment label of every cell. Built
// in memory from a planned configuration, or read from a `gather plan` output
// directory (plan.yaml + the 16-bit labels.png beside it).
#include <cstdint>
#include <string>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/plan/plan_file.hpp"

namespace gather {
namespace mission {

struct MissionPlan {
  std::string source;   // the plan.yaml it was read from ("" for a plan built in memory): errors name it
  plan::PlanFile file;  // roles, routes, cycle_period_s, estimates
  // 0 = no segment, k = segment k. A plan built in memory has its grid's
  // frame. One read from labels.png, which stores no placement, has the
  // image's size, resolution 1 and origin 0 until it is reframed on the grid
  // check_plan() accepted (the simulator and the agents' plan loader do).
  LabelImage labels;
};

// Reads `plan_yaml` (or PLAN_DIR/plan.yaml when given a directory) and the
// labels image it names (16-bit PNG, image row 0 = top of the map). Throws
// gather::Error naming the file on I/O or format errors.
MissionPlan load_mission_plan(const std::string& plan_path);

// The structure executing a plan relies on, for a team of `team` agents on
// `grid` (the plan's grid; docs/input_limits.md): ids 0..team-1 once each,
// listed by id (agents[k] is agent k),
// collectors the agents 0..N_c-1 with their own id as collector index and
// route index, one worker per segment 1..N_w delivering to the OC or to a
// collector whose route has a meeting area for its segment; cycle_period_s
// in (0, kMaxPeriod] s, area_tile_m in [a grid cell, 1e6] m; routes: finite waypoints within
// the map (1 m margin), length, meeting areas, passes and coverage entries
// finite and within [0, the polyline's length], segments in 1..N_w; the
// label image of the grid's size. Throws gather::Error naming plan.source
// ("plan" for a plan built in memory) and the agent or route at fault.
void check_plan(const MissionPlan& plan, int team, const OccupancyGrid& grid);

// The agent that drives each collector 0..N_c-1 of `plan` (check_plan made
// it collector k = agent k; a message to a worker's collector goes to this
// agent). None for a collector no agent drives (a plan check_plan refuses).
PerCollector<AgentId> collector_agents(const plan::PlanFile& plan);

}  // namespace mission
}  // namespace gather
