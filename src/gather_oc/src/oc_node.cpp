// oc_node: the Operation Center, a thin ROS wrapper around the OC role and
// the lockstep clock of gather_agent. It plans the scenario (or takes
// ~plan), tells the fleet where the plan is (/gather/plan_dir), announces
// it over LCM, drives the mission tick by tick, publishes /map and RViz
// markers, and at the end writes goals.csv, cycles.csv, summary.csv,
// agents.csv and mission.yaml into ~results_dir and prints a summary line.
// Exit status: 0 mission complete, 1 a runtime failure (agents silent, the
// mission unfinished at its time limit), 2 bad input.
#include <ros/ros.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_core/error.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_oc/launch_paths.hpp"
#include "gather_oc/ros_conversions.hpp"

namespace {

int fail(int status, const std::string& what) {
  std::fprintf(stderr, "oc_node: %s\n", what.c_str());
  return status;
}

// The plan directory, checked against the scenario it must have been made for.
std::unique_ptr<gather::agent::LoadedPlan> load_matching_plan(const std::string& dir, const std::string& scenario) {
  auto plan = std::make_unique<gather::agent::LoadedPlan>(gather::agent::load_plan(dir));
  if (std::filesystem::weakly_canonical(plan->plan.file.scenario) != std::filesystem::weakly_canonical(scenario))
    throw gather::Error(dir + "/plan.yaml", "was planned for scenario " + plan->plan.file.scenario + ", not " + scenario);
  return plan;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "oc");
  // The scenario is the one positional argument and is loaded before the node
  // talks to the ROS master, so bad input fails fast with one line.
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 2 && args.size() != 3)
    return fail(2, "usage: oc_node SCENARIO [PLAN_DIR] (no PLAN_DIR: plan the scenario; settings as private "
                   "parameters ~results_dir, ~cycles, ~seed, ~rate, ~tick, ~lcm_url)");
  const std::string scenario_path = gather::resolve_launch_path(args[1]);
  gather::Scenario scenario;
  std::unique_ptr<gather::agent::LoadedPlan> plan;
  std::string plan_dir = args.size() == 3 ? gather::resolve_launch_path(args[2]) : "";
  try {
    scenario = gather::load_scenario(scenario_path);
    if (!plan_dir.empty()) plan = load_matching_plan(plan_dir, scenario_path);
  } catch (const std::exception& e) {
    return fail(2, e.what());
  }
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  nh.deleteParam("/gather/plan_dir");  // a previous run's, on a master that outlived it
  std::string results_dir, lcm_url, reply_url, clock;
  int cycles = 0, seed = -1, loss_seed = 1;
  double rate = 0.0, tick = 0.1, loss = 0.0, marker_hz = 2.0, ready_timeout = 60.0;
  pnh.param<std::string>("results_dir", results_dir, "results/mission");
  pnh.param<std::string>("lcm_url", lcm_url, "");
  pnh.param<std::string>("reply_url", reply_url, "");
  pnh.param<std::string>("clock", clock, "lockstep");
  pnh.param("cycles", cycles, 0);
  pnh.param("seed", seed, -1);
  pnh.param("rate", rate, 0.0);
  pnh.param("tick", tick, 0.1);
  pnh.param("loss", loss, 0.0);
  pnh.param("loss_seed", loss_seed, 1);
  pnh.param("marker_rate", marker_hz, 2.0);
  pnh.param("ready_timeout", ready_timeout, 60.0);
  results_dir = gather::resolve_launch_path(results_dir);
  if (cycles < 0 || cycles > 100000) return fail(2, "~cycles must be in 0..100000 (0: the scenario's), got " + std::to_string(cycles));
  if (clock != "lockstep" && clock != "wall") return fail(2, "~clock must be lockstep or wall, got '" + clock.substr(0, 40) + "'");
  if (!(rate >= 0.0)) return fail(2, "~rate must be >= 0 (0: as fast as the lockstep allows)");
  if (clock == "wall" && rate == 0.0) rate = 1.0;  // the wall clock runs at real time unless told otherwise
  if (!(tick > 0.0 && tick <= 0.1)) return fail(2, "~tick must be in (0, 0.1] s");
  if (!(loss >= 0.0 && loss < 1.0)) return fail(2, "~loss must be in [0, 1)");
  if (!(marker_hz > 0.0)) return fail(2, "~marker_rate must be > 0 Hz");
  if (!(ready_timeout > 0.0)) return fail(2, "~ready_timeout must be > 0 s");

  // No plan given: the scenario's best configuration.
  if (!plan) {
    plan_dir = results_dir + "/plan";
    try {
      const std::string best = gather::plan::plan_scenario(scenario_path, plan_dir);
      ROS_INFO("oc: planned %s: %s -> %s", scenario_path.c_str(), best.c_str(), plan_dir.c_str());
      plan = load_matching_plan(plan_dir, scenario_path);
    } catch (const std::exception& e) {
      return fail(2, e.what());
    }
  }
  plan_dir = std::filesystem::weakly_canonical(plan_dir).string();
  gather::agent::MissionParams params = gather::agent::mission_params(plan->scenario);
  if (cycles > 0) params.cycles = cycles;
  if (seed >= 0) params.seed = static_cast<unsigned>(seed);

  // What can still be wrong with the plan or the settings is bad input (2);
  // what goes wrong after this is a runtime failure (1).
  std::unique_ptr<gather::mission::World> world_ptr;
  std::unique_ptr<gather::agent::TeamSetup> team_ptr;
  std::unique_ptr<gather::agent::LcmFleet> fleet_ptr;
  try {
    world_ptr = std::make_unique<gather::mission::World>(plan->scenario);
    team_ptr = std::make_unique<gather::agent::TeamSetup>(*world_ptr, plan->plan, params);
    const std::string replies = reply_url.empty() ? gather::agent::LcmFleet::reply_url_for(lcm_url) : reply_url;
    fleet_ptr = std::make_unique<gather::agent::LcmFleet>(lcm_url, replies, true, team_ptr->agents());
  } catch (const std::exception& e) {
    return fail(2, e.what());
  }
  gather::agent::TeamSetup& team = *team_ptr;
  gather::agent::LcmFleet& fleet = *fleet_ptr;

  ros::Publisher map_pub = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, /*latch=*/true);
  ros::Publisher marker_pub = nh.advertise<visualization_msgs::MarkerArray>("gather/markers", 1, /*latch=*/true);
  map_pub.publish(gather::to_map_msg(scenario.grid, "map", ros::Time::now()));
  nh.setParam("/gather/plan_dir", plan_dir);  // fleet_node starts the agents with it

  try {
    gather::agent::MasterOptions mo;
    mo.tick = tick, mo.rate = rate, mo.loss = loss, mo.loss_seed = static_cast<uint64_t>(loss_seed);
    mo.ready_timeout_s = ready_timeout;
    if (clock == "wall") mo.clock = gather::agent::ClockMode::kWall;
    gather::agent::LockstepMaster master(team, fleet, gather::agent::plan_digest(*plan), mo);
    const gather::plan::PlanFile& pf = plan->plan.file;
    ROS_INFO("oc: %s with %d collectors, %d agents, %d cycles of %.1f s; waiting for the fleet", pf.method.c_str(),
             pf.collectors, team.agents(), params.cycles, team.period);
    marker_pub.publish(gather::team_markers(scenario.oc, master.agents(), "map", ros::Time::now(), false));
    master.start(nullptr);
    ROS_INFO("oc: all %d agents ready, mission starts (tick %.2f s, %s)", team.agents(), tick,
             rate > 0 ? (std::to_string(rate) + "x real time").c_str() : "as fast as the lockstep allows");
    using Clock = std::chrono::steady_clock;
    auto next_marker = Clock::now();
    const auto marker_period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / marker_hz));
    bool more = true;
    while (more && ros::ok()) {
      more = master.tick(nullptr);
      if (Clock::now() >= next_marker) {
        marker_pub.publish(gather::team_markers(scenario.oc, master.agents(), "map", ros::Time::now(), true));
        next_marker = Clock::now() + marker_period;
        ros::spinOnce();
      }
    }
    marker_pub.publish(gather::team_markers(scenario.oc, master.agents(), "map", ros::Time::now(), true));
    const gather::agent::RunOutcome out = master.finish();
    gather::agent::RunSettings settings{clock == "wall" ? "lcm, wall clock" : "lcm", tick, rate, loss};
    gather::agent::write_mission_yaml(results_dir + "/mission.yaml", *plan, params, settings, out);
    if (!out.completed) return fail(1, out.failure + (ros::ok() ? "" : " (stopped)") + "; " + results_dir + "/mission.yaml");
    gather::agent::RunFiles files;
    files.add(pf, params, out);
    files.write(results_dir);
    std::printf("oc: mission done: %s Nc=%d, %d cycles, %zu goals requested, refresh %.1f s (est. %.1f), %.2f goals "
                "per cycle (est. %.2f); %lld ticks in %.1f s = %.0fx real time -> %s\n",
                pf.method.c_str(), pf.collectors, params.cycles, out.result.goals.size(), out.result.refresh_mean_s,
                pf.est_refresh_s, out.result.goals_per_cycle, pf.est_goals, static_cast<long long>(out.ticks),
                out.wall_ms / 1000.0, out.wall_ms > 0 ? out.end_s * 1000.0 / out.wall_ms : 0.0, results_dir.c_str());
    std::fflush(stdout);
  } catch (const std::exception& e) {
    nh.deleteParam("/gather/plan_dir");
    return fail(1, e.what());
  }
  nh.deleteParam("/gather/plan_dir");
  return 0;
}
