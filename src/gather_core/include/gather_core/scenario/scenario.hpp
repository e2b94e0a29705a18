#pragma once
// The scenario file of DESIGN.md: map, OC, team, radio, mission, planner.
#include <string>
#include <vector>

#include "gather_core/grid/map_loader.hpp"
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

struct TeamParams {
  int agents = 20;      // N >= 1
  double speed = 0.5;   // [m/s] > 0
  double radius = 0.2;  // [m] robot radius: routes keep this clearance (extension of DESIGN's format)
};

// received [dBm] = tx - ref_loss - 10*exponent*log10(d / 1 m) - wall_loss * min(walls, max_walls)
struct RadioParams {
  double tx_power_dbm = 0.0;
  double ref_loss_db = 40.0;
  double exponent = 3.0;
  double wall_loss_db = 5.0;  // per wall crossed (a run of non-free cells along the ray)
  int max_walls = 4;
  double sensitivity_dbm = -75.0;  // a link exists when received >= sensitivity
  // Data rate of a worker-to-collector hand-over [bit/s], in [0, 1e12]; 0 =
  // instant hand-over (the link needs to hold for one instant). With a rate,
  // handing over n goals needs the link to hold for transfer_s(n) seconds
  // (docs/simulator.md, "Hand-over").
  double bitrate_bps = 0.0;
};

// [s] the longest time between two requests (mission.period, plan.yaml's
// cycle_period_s, the planner's automatic period): a run's time grows with
// the mission's ticks, and a period of 1e6 s made two cycles of `gather
// run` take minutes (docs/input_limits.md).
constexpr double kMaxPeriod = 1e5;

struct MissionParams {
  int goals_per_request = 40;
  int cycles = 10;
  unsigned seed = 1;
  // Time between two OC requests [s]; 0 = automatic: the time to travel from
  // the OC's coverage to the farthest reachable point at team speed
  // (extension of DESIGN's format; see docs/planner.md).
  double period = 0.0;
  // Size of one goal's measurement [byte], in [0, 1e9]: with
  // radio.bitrate_bps it sets how long a hand-over takes.
  double bytes_per_goal = 4096.0;
};

// Which refresh time the utility weighs (docs/planner.md, "Two refresh
// metrics"): latency = delivered_at - requested_at per goal; interval = per
// area, the time between consecutive deliveries of its data to the OC.
enum class RefreshMetric { kLatency, kInterval };
const char* refresh_metric_name(RefreshMetric m);

struct PlannerParams {
  std::vector<std::string> methods{"bap", "pap", "rap"};
  int collectors_min = 0;  // inclusive range of N_c to sweep
  int collectors_max = 8;  // default: min(8, N - 1)
  double alpha = 0.5;
  double beta = 0.5;
  RefreshMetric refresh = RefreshMetric::kInterval;
  // Plan and simulate on a coarser grid when the map has more cells than
  // this (0 = always the map's grid); extension of DESIGN's format, see
  // grid/planning_grid.hpp and docs/planner.md.
  std::size_t max_cells = 250000;
};

struct Scenario;
// Time [s] a hand-over of n goals needs the worker-collector link to hold:
// n * mission.bytes_per_goal * 8 / radio.bitrate_bps, 0 when the rate is 0.
double transfer_s(const Scenario& s, std::size_t n);

struct Scenario {
  std::string path;      // the scenario file
  std::string map_path;  // its map_server YAML, resolved
  MapMetadata map_meta;
  OccupancyGrid grid;
  Point2 oc;  // [m], map frame
  TeamParams team;
  RadioParams radio;
  MissionParams mission;
  PlannerParams planner;
};

// Loads and validates a scenario and its map. Unknown keys, missing required
// keys (`map`, `oc`), values out of range, an OC outside the map or not on a
// free cell all throw gather::Error naming the file and the problem.
Scenario load_scenario(const std::string& path);

// The scenario's settings without its map (grid empty): `map:` may be absent
// unless `map_required` (map_path is then empty). For a map that comes from
// elsewhere (a ROS map topic): attach it with attach_map().
Scenario load_scenario_settings(const std::string& path, bool map_required);
// Sets the scenario's grid and checks the OC against it (inside the map, on
// free space); throws gather::Error naming the scenario file.
void attach_map(Scenario& s, OccupancyGrid grid);

// The scenario on its planning grid: the map coarsened by `factor` (>= 1;
// 1 = unchanged). planning_factor() chooses the factor from
// planner.max_cells (grid/planning_grid.hpp).
int planning_factor(const Scenario& s);
Scenario on_planning_grid(const Scenario& s, int factor);

}  // namespace gather
