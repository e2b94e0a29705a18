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
  plan::PlanFile file;          // roles, routes, cycle_period_s, estimates
  int width = 0, height = 0;    // of the label image [cells]
  std::vector<int32_t> labels;  // row-major (row 0 = bottom), 0 = no segment, k = segment k
};

// Reads `plan_yaml` (or PLAN_DIR/plan.yaml when given a directory) and the
// labels image it names (16-bit PNG, image row 0 = top of the map). Throws
// gather::Error naming the file on I/O or format errors.
MissionPlan load_mission_plan(const std::string& plan_path);

}  // namespace mission
}  // namespace gather
