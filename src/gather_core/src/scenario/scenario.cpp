#include "gather_core/scenario/scenario.hpp"

#include "gather_core/grid/planning_grid.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "gather_core/error.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/yaml_fields.hpp"

namespace gather {
namespace {

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void require(bool ok, const std::string& file, const std::string& what) {
  if (!ok) throw Error(file, what);
}

}  // namespace

Scenario load_scenario_settings(const std::string& path, bool map_required) {
  const YAML::Node root = yaml::load_file(path);
  yaml::Fields f(root, path, "");
  f.allow({"map", "oc", "team", "radio", "mission", "planner"});
  Scenario s;
  s.path = path;
  if (map_required || f.has("map")) s.map_path = f.file_path("map");
  const std::vector<double> oc = f.required<std::vector<double>>("oc");
  require(oc.size() == 2, path, "oc must be [x, y] in meters");
  check_range(range::kOcX, oc[0], path);
  check_range(range::kOcY, oc[1], path);
  s.oc = Point2{oc[0], oc[1]};

  const yaml::Fields team = f.section("team");
  team.allow({"agents", "speed", "radius"});
  s.team.agents = team.optional<int>("agents", s.team.agents);
  s.team.speed = team.optional<double>("speed", s.team.speed);
  check_range(range::kTeamAgents, s.team.agents, path);
  check_range(range::kTeamSpeed, s.team.speed, path);
  s.team.radius = team.optional<double>("radius", s.team.radius);
  check_range(range::kTeamRadius, s.team.radius, path);

  const yaml::Fields radio = f.section("radio");
  radio.allow(
      {"tx_power_dbm", "ref_loss_db", "exponent", "wall_loss_db", "max_walls", "sensitivity_dbm", "bitrate_bps"});
  RadioParams& r = s.radio;
  r.tx_power_dbm = radio.optional<double>("tx_power_dbm", r.tx_power_dbm);
  r.ref_loss_db = radio.optional<double>("ref_loss_db", r.ref_loss_db);
  r.exponent = radio.optional<double>("exponent", r.exponent);
  r.wall_loss_db = radio.optional<double>("wall_loss_db", r.wall_loss_db);
  r.max_walls = radio.optional<int>("max_walls", r.max_walls);
  r.sensitivity_dbm = radio.optional<double>("sensitivity_dbm", r.sensitivity_dbm);
  check_range(range::kTxPower, r.tx_power_dbm, path);
  check_range(range::kRefLoss, r.ref_loss_db, path);
  check_range(range::kExponent, r.exponent, path);
  check_range(range::kWallLoss, r.wall_loss_db, path);
  check_range(range::kMaxWalls, r.max_walls, path);
  check_range(range::kSensitivity, r.sensitivity_dbm, path);
  {
    // The free-space range the link budget gives (RadioModel): at most 100 km.
    const double budget = r.tx_power_dbm - r.ref_loss_db - r.sensitivity_dbm;
    require(budget / (10.0 * r.exponent) <= 5.0, path,
            "radio: tx_power_dbm - ref_loss_db - sensitivity_dbm = " + num(budget) + " dB over exponent " +
                num(r.exponent) + " gives a free-space range over 100 km; lower the budget or raise radio.exponent");
  }
  r.bitrate_bps = radio.optional<double>("bitrate_bps", r.bitrate_bps);
  check_range(range::kBitrate, r.bitrate_bps, path);  // 0: instant hand-over

  const yaml::Fields mission = f.section("mission");
  mission.allow({"goals_per_request", "cycles", "seed", "period", "bytes_per_goal"});
  s.mission.goals_per_request = mission.optional<int>("goals_per_request", s.mission.goals_per_request);
  s.mission.cycles = mission.optional<int>("cycles", s.mission.cycles);
  s.mission.seed = mission.optional<unsigned>("seed", s.mission.seed);
  check_range(range::kGoalsPerRequest, s.mission.goals_per_request, path);
  check_range(range::kCycles, s.mission.cycles, path);
  // Every goal of the mission is a record of a run, and a step of the
  // planner's estimate: at most mission::kMaxGoalRecords (docs/input_limits.md).
  mission::check_goal_budget(s.mission.goals_per_request, s.mission.cycles, 1, path);
  s.mission.period = mission.optional<double>("period", s.mission.period);
  check_range(range::kPeriod, s.mission.period, path);  // 0: automatic
  check_range(range::kMissionSeed, s.mission.seed, path);
  s.mission.bytes_per_goal = mission.optional<double>("bytes_per_goal", s.mission.bytes_per_goal);
  check_range(range::kBytesPerGoal, s.mission.bytes_per_goal, path);

  const yaml::Fields planner = f.section("planner");
  planner.allow({"methods", "collectors", "alpha", "beta", "refresh", "max_cells"});
  PlannerParams& p = s.planner;
  p.methods = planner.optional<std::vector<std::string>>("methods", p.methods);
  require(!p.methods.empty(), path, "planner.methods must not be empty");
  for (const auto& m : p.methods)
    require(m == "bap" || m == "pap" || m == "rap", path,
            "planner.methods: unknown method '" + m + "' (bap, pap, rap)");
  std::vector<std::string> sorted = p.methods;
  std::sort(sorted.begin(), sorted.end());
  require(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end(), path,
          "planner.methods lists a method twice");
  p.collectors_max = std::min(p.collectors_max, s.team.agents - 1);
  if (planner.has("collectors")) {
    const std::vector<int> given = planner.required<std::vector<int>>("collectors");
    require(given.size() == 2, path, "planner.collectors must be [min, max]");
    check_range(range::kCollectorsMin, given[0], path);
    check_range(range::kCollectorsMax, given[1], path);
    p.collectors_min = given[0];
    p.collectors_max = given[1];
    require(0 <= p.collectors_min && p.collectors_min <= p.collectors_max, path,
            "planner.collectors must satisfy 0 <= min <= max");
    require(p.collectors_max <= s.team.agents - 1, path,
            "planner.collectors max " + std::to_string(p.collectors_max) + " leaves no worker (team.agents = " +
                std::to_string(s.team.agents) + ", so at most " + std::to_string(s.team.agents - 1) + ")");
  }
  p.alpha = planner.optional<double>("alpha", p.alpha);
  p.beta = planner.optional<double>("beta", p.beta);
  check_range(range::kAlpha, p.alpha, path);
  check_range(range::kBeta, p.beta, path);
  require(p.alpha + p.beta > 0, path, "planner.alpha and beta must not both be 0");
  const std::string refresh = planner.optional<std::string>("refresh", refresh_metric_name(p.refresh));
  require(refresh == "latency" || refresh == "interval", path,
          "planner.refresh must be latency or interval, got '" + refresh.substr(0, 40) + "'");
  p.refresh = refresh == "latency" ? RefreshMetric::kLatency : RefreshMetric::kInterval;
  const long long max_cells = planner.optional<long long>("max_cells", static_cast<long long>(p.max_cells));
  check_range(range::kMaxCells, static_cast<double>(max_cells), path);  // 0: the map's own grid
  p.max_cells = static_cast<std::size_t>(max_cells);
  return s;
}

double transfer_s(const Scenario& s, std::size_t n) {
  if (!(s.radio.bitrate_bps > 0.0)) return 0.0;
  return static_cast<double>(n) * s.mission.bytes_per_goal * 8.0 / s.radio.bitrate_bps;
}

Scenario load_scenario(const std::string& path) {
  Scenario s = load_scenario_settings(path, true);
  s.map_meta = read_map_metadata(s.map_path);
  attach_map(s, threshold_map_image(read_map_image(s.map_meta.image), s.map_meta));
  return s;
}

void attach_map(Scenario& s, OccupancyGrid grid) {
  const std::string& path = s.path;
  s.grid = std::move(grid);
  const Cell oc_cell = s.grid.world_to_cell(s.oc);
  require(s.grid.contains(oc_cell), path,
          "oc [" + num(s.oc.x) + ", " + num(s.oc.y) + "] is outside the map (" + num(s.grid.origin().x) + ".." +
              num(s.grid.origin().x + s.grid.width() * s.grid.resolution()) + " x " + num(s.grid.origin().y) + ".." +
              num(s.grid.origin().y + s.grid.height() * s.grid.resolution()) + " m)");
  require(s.grid.is_free(oc_cell), path,
          "oc [" + num(s.oc.x) + ", " + num(s.oc.y) + "] is on an obstacle or unknown cell, not free space");
}

int planning_factor(const Scenario& s) { return choose_planning_grid(s.grid, s.oc, s.planner.max_cells).factor; }

Scenario on_planning_grid(const Scenario& s, int factor) {
  if (factor < 1) throw Error(s.path, "planning grid factor must be >= 1, got " + std::to_string(factor));
  Scenario out = s;
  if (factor == 1) return out;
  out.grid = coarsen(s.grid, factor);
  if (!out.grid.is_free(out.grid.world_to_cell(s.oc)))
    throw Error(s.path, "the OC is not on free space of the planning grid (factor " + std::to_string(factor) + ")");
  return out;
}

const char* refresh_metric_name(RefreshMetric m) { return m == RefreshMetric::kLatency ? "latency" : "interval"; }

}  // namespace gather
