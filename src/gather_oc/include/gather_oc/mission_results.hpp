#pragma once
// The results file of a mission run (results_dir/mission.yaml): what the OC
// heard from every agent. Tests and `make run` read it, since roslaunch
// returns 0 even when a required node fails.
#include <string>

#include "gather_agent/fleet_monitor.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {

struct MissionSummary {
  double duration_s = 0.0;
  int agents_expected = 0;
  int agents_heard = 0;
  long long heartbeats = 0;
  long long missed = 0;
  long long rejected = 0;
  bool ok() const { return agents_heard == agents_expected; }
};

MissionSummary summarize(const FleetMonitor& fleet, double duration_s);

// Writes `path` (directories created); throws gather::Error on I/O failure.
void write_mission_results(const std::string& path, const Scenario& scenario, const FleetMonitor& fleet,
                           const MissionSummary& summary);

}  // namespace gather
