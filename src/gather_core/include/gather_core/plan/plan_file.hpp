#pragma once
// plan.yaml: everything the agents need to execute a configuration (the
// chosen method and N_c, the labels image, each agent's role, segment and
// collector, collector routes as waypoints [m], meeting areas, the cycle
// period and the estimates).
#include <string>
#include <vector>

#include "gather_core/plan/plan_types.hpp"

namespace gather {
namespace plan {

struct AgentAssignment {
  AgentId id;
  bool collector = false;
  SegmentId segment;        // workers: their segment 1..N_w; collectors: none (0)
  CollectorId delivers_to;  // workers: their collector 0..N_c-1, or none = the OC; collectors: their own index
};

struct PlanFile {
  static constexpr const char* kFormat = "gather-plan/2";  // 2: area_tile_m, estimates.interval_s
  std::string scenario;                                    // absolute path of the scenario file
  std::string method;                                      // bap | pap | rap
  int collectors = 0;
  int workers = 0;
  unsigned seed = 1;
  std::string labels_png;  // relative to the plan file
  int grid_factor = 1;     // the labels are on the map coarsened by this (grid/planning_grid.hpp)
  double cycle_period_s = 0.0;
  double area_tile_m = 0.0;  // side of the square areas of the refresh interval (mission::area_of)
  double est_refresh_s = 0.0;
  double est_goals = 0.0;
  double est_interval_s = 0.0;
  double utility = 0.0;
  PerAgent<AgentAssignment>
      agents;  // agents[k] is agent k: read_plan_file sorts them by id, check_plan refuses otherwise
  PerCollector<CollectorRoute> routes;
  std::vector<WorkerEstimate> workers_est;
};

// Throws gather::Error naming the file on I/O or format errors.
void write_plan_file(const std::string& path, const PlanFile& plan);
PlanFile read_plan_file(const std::string& path);

}  // namespace plan
}  // namespace gather
