// oc_node: the Operation Center, a thin ROS wrapper around the OC role and
// the lockstep clock of gather_agent. It takes the map (the scenario's, or
// one from ~map_topic as map_server publishes it), plans the scenario (or
// takes PLAN_DIR), tells the fleet where the plan is (/gather/plan_dir),
// announces it over LCM, drives the mission tick by tick and publishes it
// to ROS (MissionPublisher: /clock with use_sim_time, /map, markers, TF,
// poses, mission topics). At the end it writes goals.csv, cycles.csv,
// summary.csv, agents.csv and mission.yaml into ~results_dir, prints a
// summary line and, with ~close_on_end, ends the roslaunch that started it
// (quietly, as Ctrl-C does); otherwise it stays up (latched topics stay
// available) until it is stopped.
// Exit status: 0 mission complete, 1 a runtime failure (agents silent, the
// mission unfinished at its time limit), 2 bad input.
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <thread>

#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/shutdown_signal.hpp"
#include "gather_core/error.hpp"
#include "gather_core/figures/plan_figures.hpp"
#include "gather_core/grid/map_saver.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_msgs/FleetEnded.h"
#include "gather_oc/launch_end.hpp"
#include "gather_oc/launch_paths.hpp"
#include "gather_oc/mission_publisher.hpp"
#include "gather_oc/params.hpp"
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
    throw gather::Error(dir + "/plan.yaml",
                        "was planned for scenario " + plan->plan.file.scenario + ", not " + scenario);
  return plan;
}

// What executing a plan depends on besides the map.
bool same_settings(const gather::Scenario& a, const gather::Scenario& b) {
  const auto& ra = a.radio;
  const auto& rb = b.radio;
  return a.oc.x == b.oc.x && a.oc.y == b.oc.y && a.team.agents == b.team.agents && a.team.speed == b.team.speed &&
         a.team.radius == b.team.radius && ra.tx_power_dbm == rb.tx_power_dbm && ra.ref_loss_db == rb.ref_loss_db &&
         ra.exponent == rb.exponent && ra.wall_loss_db == rb.wall_loss_db && ra.max_walls == rb.max_walls &&
         ra.sensitivity_dbm == rb.sensitivity_dbm && a.mission.goals_per_request == b.mission.goals_per_request &&
         a.mission.cycles == b.mission.cycles && a.mission.seed == b.mission.seed &&
         a.mission.period == b.mission.period;
}

bool same_map(const gather::OccupancyGrid& a, const gather::OccupancyGrid& b) {
  return a.width() == b.width() && a.height() == b.height() && std::abs(a.resolution() - b.resolution()) < 1e-6 &&
         std::abs(a.origin().x - b.origin().x) < 1e-6 && std::abs(a.origin().y - b.origin().y) < 1e-6 &&
         a.free_mask() == b.free_mask();
}

// Settings users change per run (private parameters; mission.launch's arguments).
struct Settings {
  std::string results_dir, lcm_url, reply_url, clock, frame, kill, restart, revoke, repair, key_file, robots, agents;
  int cycles = 0, seed = -1, loss_seed = 1;
  double rate = 0.0, tick = 0.1, loss = 0.0, ready_timeout = 60.0, map_timeout = 30.0, view_period = 0.5;
  double silent_intervals = 2.0;
  bool close_on_end = false, sim_time = false, insecure = false, laser = false;
};

// Reads and checks them; "" when they are fine, else what is wrong.
std::string read_settings(ros::NodeHandle& pnh, ros::NodeHandle& nh, Settings& s) {
  using gather::typed_param;
  std::string bad;
  auto read = [&](const std::string& e) {
    if (bad.empty()) bad = e;
  };
  read(typed_param<std::string>(pnh, "results_dir", s.results_dir, "results/mission"));
  read(typed_param<std::string>(pnh, "lcm_url", s.lcm_url, ""));
  if (s.lcm_url == "default") s.lcm_url.clear();  // mission.launch's "not given"
  read(typed_param<std::string>(pnh, "reply_url", s.reply_url, ""));
  read(typed_param<std::string>(pnh, "key_file", s.key_file, "auto"));
  read(typed_param(pnh, "insecure", s.insecure, false));
  read(typed_param<std::string>(pnh, "clock", s.clock, "lockstep"));
  read(typed_param<std::string>(pnh, "frame_id", s.frame, "map"));
  read(typed_param(pnh, "cycles", s.cycles, 0));
  read(typed_param(pnh, "seed", s.seed, -1));
  read(typed_param(pnh, "rate", s.rate, 0.0));
  read(typed_param(pnh, "tick", s.tick, 0.1));
  read(typed_param(pnh, "loss", s.loss, 0.0));
  read(typed_param(pnh, "loss_seed", s.loss_seed, 1));
  read(typed_param<std::string>(pnh, "kill", s.kill, "none"));
  read(typed_param<std::string>(pnh, "restart", s.restart, "none"));
  read(typed_param<std::string>(pnh, "revoke", s.revoke, "none"));
  read(typed_param<std::string>(pnh, "repair", s.repair, "merge"));
  read(typed_param(pnh, "silent_intervals", s.silent_intervals, 2.0));
  read(typed_param(pnh, "ready_timeout", s.ready_timeout, 60.0));
  read(typed_param(pnh, "map_timeout", s.map_timeout, 30.0));
  read(typed_param(pnh, "view_period", s.view_period, 0.5));
  read(typed_param(pnh, "close_on_end", s.close_on_end, false));
  read(typed_param<std::string>(pnh, "robots", s.robots, "ideal"));
  read(typed_param<std::string>(pnh, "agents", s.agents, "spawn"));
  read(typed_param(pnh, "laser", s.laser, false));
  if (!bad.empty()) return bad;
  nh.param("/use_sim_time", s.sim_time, false);
  s.results_dir = gather::resolve_launch_path(s.results_dir);
  if (s.cycles < 0 || s.cycles > 100000)
    return "~cycles must be in 0..100000 (0: the scenario's), got " + std::to_string(s.cycles);
  if (s.clock != "lockstep" && s.clock != "wall")
    return "~clock must be lockstep or wall, got '" + s.clock.substr(0, 40) + "'";
  if (!(s.rate >= 0.0 && s.rate <= 1e6)) return "~rate must be in [0, 1e6] (0: as fast as the lockstep allows)";
  if (s.clock == "wall" && s.rate == 0.0) s.rate = 1.0;  // the wall clock runs at real time unless told otherwise
  if (!(s.tick > 0.0 && s.tick <= 0.1)) return "~tick must be in (0, 0.1] s";
  if (!(s.loss >= 0.0 && s.loss < 1.0)) return "~loss must be in [0, 1)";
  if (s.loss_seed < 0) return "~loss_seed must be >= 0";
  if (s.repair != "merge" && s.repair != "none")
    return "~repair must be merge or none, got '" + s.repair.substr(0, 40) + "'";
  if (s.robots != "ideal" && s.robots != "mrpt" && s.robots != "external")
    return "~robots must be ideal, mrpt or external, got '" + s.robots.substr(0, 40) + "'";
  if (s.agents != "spawn" && s.agents != "external")
    return "~agents must be spawn (fleet_node starts them) or external (they run on the robots: robot.launch), got '" +
           s.agents.substr(0, 40) + "'";
  if (s.agents == "external" && (s.robots != "external" || s.clock != "wall"))
    return "~agents external needs robots:=external clock:=wall (agents on real robots, on their own clocks)";
  if (s.agents == "external" && (s.kill != "none" || s.restart != "none"))
    return "~agents external: the OC starts no agent, so it kills or restarts none (no ~kill, ~restart)";
  if (s.agents == "external" && s.laser)
    return "~laser with ~agents external is not built: fleet_node relays the robots' scans, and it does not run "
           "when the agents run on the robots";
  // Agents on robots are started by hand, one robot after another.
  if (s.agents == "external" && !pnh.hasParam("ready_timeout"))
    s.ready_timeout = gather::agent::kExternalReadyTimeout_s;
  if (s.laser && s.robots == "ideal")
    return "~laser needs robots (robots:=mrpt or external): ideal bases have no laser";
  if (!(s.silent_intervals >= 1.5 && s.silent_intervals <= 100.0)) return "~silent_intervals must be in [1.5, 100]";
  if (!(s.ready_timeout > 0.0 && s.ready_timeout <= 86400.0)) return "~ready_timeout must be in (0, 86400] s";
  if (!(s.map_timeout > 0.0 && s.map_timeout <= 86400.0)) return "~map_timeout must be in (0, 86400] s";
  if (!(s.view_period >= s.tick && s.view_period <= 3600.0))
    return "~view_period must be in [~tick, 3600] s of mission time";
  if (s.frame.empty()) return "~frame_id must not be empty";
  if (s.key_file.empty()) return "~key_file must not be empty (auto: results_dir/fleet.key, made if missing)";
  if (s.insecure && s.key_file != "auto") return "give ~key_file or ~insecure, not both";
  if (s.key_file != "auto") s.key_file = gather::resolve_launch_path(s.key_file);
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // a line at a time, also into a log file or a pipe
  ros::init(argc, argv, "oc");
  // The scenario is the one positional argument and is loaded before the node
  // talks to the ROS master, so bad input fails fast with one line.
  std::vector<std::string> all, args;
  ros::removeROSArgs(argc, argv, all);
  // mission.launch passes --plan=auto and --map-topic=none for "not given"
  // (roslaunch --ros-args lists an argument with an empty default as required).
  std::string map_topic, plan_flag, default_scenario;
  for (std::size_t i = 1; i < all.size(); ++i) {
    if (all[i].rfind("--map-topic=", 0) == 0)
      map_topic = all[i].substr(12);
    else if (all[i].rfind("--plan=", 0) == 0)
      plan_flag = all[i].substr(7);
    else if (all[i].rfind("--default-scenario=", 0) == 0)
      default_scenario = all[i].substr(19);
    else
      args.push_back(all[i]);
  }
  if (map_topic == "none") map_topic.clear();
  if (plan_flag == "auto") plan_flag.clear();
  if (!plan_flag.empty()) args.push_back(plan_flag);
  if (args.size() != 1 && args.size() != 2)
    return fail(2,
                "usage: oc_node SCENARIO|auto [PLAN_DIR | --plan=PLAN_DIR|auto] [--map-topic=TOPIC|none] "
                "[--default-scenario=FILE] (no plan: plan the scenario; auto: the plan's scenario, else "
                "--default-scenario; --map-topic: take the map from a map_server topic; settings as private "
                "parameters, see the README)");
  std::string plan_dir = args.size() == 2 ? gather::resolve_launch_path(args[1]) : "";
  // SCENARIO "auto" (mission.launch's default): the one the plan names, else
  // --default-scenario.
  std::string scenario_path;
  if (args[0] != "auto") {
    scenario_path = gather::resolve_launch_path(args[0]);
  } else if (!plan_dir.empty()) {
    try {
      scenario_path = gather::plan::read_plan_file(plan_dir + "/plan.yaml").scenario;
    } catch (const std::exception& e) {
      return fail(2, e.what());
    }
  } else if (!default_scenario.empty()) {
    scenario_path = default_scenario;
  } else {
    return fail(2, "SCENARIO auto needs a plan (its plan.yaml names the scenario) or --default-scenario=FILE");
  }
  const bool map_from_topic = !map_topic.empty();
  gather::Scenario scenario;
  std::unique_ptr<gather::agent::LoadedPlan> plan;
  try {
    if (!map_from_topic) {
      scenario = gather::load_scenario(scenario_path);
      if (!plan_dir.empty()) plan = load_matching_plan(plan_dir, scenario_path);
    } else {
      scenario = gather::load_scenario_settings(scenario_path, false);  // the map comes later
    }
  } catch (const std::exception& e) {
    return fail(2, e.what());
  }
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  Settings set;
  if (const std::string bad = read_settings(pnh, nh, set); !bad.empty()) return fail(2, bad);
  nh.deleteParam("/gather/plan_dir");  // a previous run's, on a master that outlived it
  nh.deleteParam("/gather/key_file");
  nh.deleteParam("/gather/fleet_status");

  // The map from a topic (map_server, or any OccupancyGrid publisher): saved
  // as map_server files beside the results, with a copy of the scenario that
  // names them, so the agents load the very same map.
  if (map_from_topic) {
    try {
      ROS_INFO("oc: waiting for the map on %s", map_topic.c_str());
      // (Wall time: with use_sim_time the clock is not running yet.)
      nav_msgs::OccupancyGrid::ConstPtr msg;
      ros::Subscriber sub = nh.subscribe<nav_msgs::OccupancyGrid>(
          map_topic, 1, [&msg](const nav_msgs::OccupancyGrid::ConstPtr& m) { msg = m; });
      const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(set.map_timeout);
      while (!msg && ros::ok() && ros::WallTime::now() < until) {
        ros::spinOnce();
        ros::WallDuration(0.02).sleep();
      }
      sub.shutdown();
      if (!msg) {
        char why[160];
        std::snprintf(why, sizeof why, ": no map received within %g s (~map_timeout)", set.map_timeout);
        return fail(2, map_topic + why);
      }
      gather::OccupancyGrid grid = gather::from_map_msg(*msg, map_topic);
      try {  // the OC on this map: errors name the user's scenario, and the topic
        gather::Scenario check = scenario;
        gather::attach_map(check, grid);
      } catch (const std::exception& e) {
        throw std::runtime_error(std::string(e.what()) + " (on the map received on " + map_topic + ")");
      }
      const std::string map_yaml = gather::save_map(grid, set.results_dir + "/map/map");
      const std::string derived = set.results_dir + "/map/scenario.yaml";
      gather::write_scenario_with_map(scenario_path, std::filesystem::absolute(map_yaml).string(), derived);
      ROS_INFO("oc: map %dx%d cells of %.3f m from %s -> %s", grid.width(), grid.height(), grid.resolution(),
               map_topic.c_str(), map_yaml.c_str());
      if (!plan_dir.empty()) {
        // A given plan must have been made on this map.
        plan = std::make_unique<gather::agent::LoadedPlan>(gather::agent::load_plan(plan_dir));
        const gather::Scenario planned = gather::load_scenario(plan->plan.file.scenario);
        const gather::Scenario received = gather::load_scenario(derived);
        if (!same_map(planned.grid, received.grid))
          throw gather::Error(plan_dir + "/plan.yaml", "was planned on the map of " + plan->plan.file.scenario +
                                                           ", not on the map received on " + map_topic);
        if (!same_settings(planned, received))
          throw gather::Error(plan_dir + "/plan.yaml", "was planned for scenario " + plan->plan.file.scenario +
                                                           ", whose OC, team, radio or mission differ from " +
                                                           scenario_path + "'s");
        scenario_path = plan->plan.file.scenario;
      } else {
        scenario_path = derived;
      }
      scenario = gather::load_scenario(scenario_path);
    } catch (const std::exception& e) {
      return fail(2, e.what());
    }
  }

  // No plan given: the scenario's best configuration.
  if (!plan) {
    plan_dir = set.results_dir + "/plan";
    try {
      const std::string best =
          gather::plan::plan_scenario(scenario_path, plan_dir, 2, gather::figures::write_plan_figures);
      ROS_INFO("oc: planned %s: %s -> %s", scenario_path.c_str(), best.c_str(), plan_dir.c_str());
      plan = load_matching_plan(plan_dir, scenario_path);
    } catch (const std::exception& e) {
      return fail(2, e.what());
    }
  }
  plan_dir = std::filesystem::weakly_canonical(plan_dir).string();
  gather::agent::MissionParams params = gather::agent::mission_params(plan->scenario);
  if (set.cycles > 0) params.cycles = set.cycles;
  try {
    gather::mission::check_goal_budget(plan->scenario.mission.goals_per_request, params.cycles, 1, plan->scenario.path);
  } catch (const std::exception& e) {
    return fail(2, e.what());
  }
  if (set.seed >= 0) params.seed = static_cast<unsigned>(set.seed);
  params.repair = set.repair == "none" ? gather::mission::RepairMode::kNone : gather::mission::RepairMode::kMerge;
  params.silent_intervals = set.silent_intervals;
  // On robots: the protocol's robot settings (mission::robot_protocol), as gather run --robots.
  if (set.robots != "ideal") params.protocol = gather::mission::robot_protocol(params.protocol);

  // What can still be wrong with the plan or the settings is bad input (2);
  // what goes wrong after this is a runtime failure (1).
  std::unique_ptr<gather::mission::World> world_ptr;
  std::unique_ptr<gather::agent::TeamSetup> team_ptr;
  std::unique_ptr<gather::agent::LcmFleet> fleet_ptr;
  std::unique_ptr<gather::agent::LockstepMaster> master_ptr;
  gather::agent::MasterOptions mo;
  // The agent processes fleet_node started that ended (/gather/fleet/ended,
  // latched), read on a queue of their own whenever the master looks: one
  // it waits on that ended stops the mission at once, naming its status.
  ros::CallbackQueue fleet_queue;
  std::vector<std::pair<int, int>> fleet_ended;
  ros::Subscriber fleet_sub;
  if (set.agents != "external") {
    ros::SubscribeOptions so = ros::SubscribeOptions::create<gather_msgs::FleetEnded>(
        "/gather/fleet/ended", 1,
        [&fleet_ended](const gather_msgs::FleetEnded::ConstPtr& m) {
          fleet_ended.clear();
          for (std::size_t k = 0; k < m->agents.size() && k < m->exit_status.size(); ++k)
            fleet_ended.emplace_back(m->agents[k], m->exit_status[k]);
        },
        ros::VoidPtr(), &fleet_queue);
    fleet_sub = nh.subscribe(so);
    mo.ended = [&fleet_queue, &fleet_ended] {
      fleet_queue.callAvailable();
      return fleet_ended;
    };
  }
  try {
    world_ptr = std::make_unique<gather::mission::World>(plan->scenario);
    team_ptr = std::make_unique<gather::agent::TeamSetup>(*world_ptr, plan->plan, params);
    const std::string replies =
        set.reply_url.empty() ? gather::agent::LcmFleet::reply_url_for(set.lcm_url) : set.reply_url;
    // The fleet key (docs/security.md): ~key_file, or with "auto" one kept
    // beside the results (made on the first run); fleet_node hands the same
    // file to the agents it starts (/gather/key_file).
    std::optional<gather::agent::FleetKey> key;
    if (set.insecure) {
      key = gather::agent::fleet_key_from_options("", true, "oc", "~key_file", "~insecure");
    } else {
      std::filesystem::create_directories(set.results_dir);
      if (set.key_file == "auto") set.key_file = set.results_dir + "/fleet.key";
      bool created = false;
      key = gather::agent::load_or_create_fleet_key(set.key_file, &created);
      ROS_INFO("oc: fleet traffic signed with key %d from %s%s", key->id, set.key_file.c_str(),
               created ? " (made now: copy it to every robot)" : "");
    }
    fleet_ptr = std::make_unique<gather::agent::LcmFleet>(set.lcm_url, replies, true, key, team_ptr->agents());
    mo.tick = set.tick, mo.rate = set.rate, mo.loss = set.loss, mo.loss_seed = static_cast<uint64_t>(set.loss_seed);
    mo.ready_timeout_s = set.ready_timeout;
    mo.observe = true;
    // The OC revokes these agents' keys (docs/security.md, "Revocation").
    for (const gather::agent::Kill& r : gather::agent::parse_kills(set.revoke, team_ptr->agents(), "~revoke"))
      team_ptr->params.revoke.emplace_back(static_cast<int16_t>(r.agent), r.at);
    mo.kills = gather::agent::parse_kills(set.kill, team_ptr->agents(), "~kill");
    mo.restarts = gather::agent::parse_kills(set.restart, team_ptr->agents(), "~restart");  // fleet_node respawns them
    if (!mo.kills.empty() && set.clock == "wall") throw gather::Error("~kill", "needs the lockstep clock");
    if (!mo.restarts.empty() && set.clock == "wall") throw gather::Error("~restart", "needs the lockstep clock");
    for (const gather::agent::Kill& r : mo.restarts)
      for (const gather::agent::Kill& k : mo.kills)
        if (r.agent == k.agent)
          throw gather::Error("~restart", "agent " + std::to_string(r.agent) + " is also in ~kill");
    if (set.clock == "wall") mo.clock = gather::agent::ClockMode::kWall;
    mo.robots = set.robots != "ideal";
    master_ptr =
        std::make_unique<gather::agent::LockstepMaster>(*team_ptr, *fleet_ptr, gather::agent::plan_digest(*plan), mo);
  } catch (const std::exception& e) {
    return fail(2, e.what());
  }
  gather::agent::TeamSetup& team = *team_ptr;
  gather::agent::LockstepMaster& master = *master_ptr;

  gather::PublisherOptions po;
  po.frame = set.frame;
  po.publish_map = map_topic.empty();
  po.sim_time = set.sim_time;
  po.view_period = set.view_period;
  po.robots = set.robots != "ideal";
  gather::MissionPublisher pub(nh, team, scenario.grid, po);
  nh.setParam("/gather/key_file", set.insecure ? std::string() : set.key_file);  // "": --insecure
  nh.setParam("/gather/plan_dir", plan_dir);                                     // fleet_node starts the agents with it

  int status = 0;
  std::string failure;
  const gather::plan::PlanFile& pf = plan->plan.file;
  // Ctrl-C (roslaunch's SIGINT) interrupts the waits for the fleet and its replies.
  gather::ShutdownSignal stop([] { return !ros::ok(); });
  try {
    if (set.agents == "external")
      ROS_INFO(
          "oc: %s with %d collectors, %d agents, %d cycles of %.1f s; waiting up to %.0f s for the %d agents of "
          "the plan on %s (started on the robots: robot.launch)",
          pf.method.c_str(), pf.collectors, team.agents(), params.cycles, team.period, set.ready_timeout, team.agents(),
          gather::agent::effective_url(set.lcm_url).c_str());
    else
      ROS_INFO("oc: %s with %d collectors, %d agents, %d cycles of %.1f s; waiting for the fleet", pf.method.c_str(),
               pf.collectors, team.agents(), params.cycles, team.period);
    pub.before_start(master);
    master.start(&stop);
    ROS_INFO("oc: all %d agents ready, mission starts (tick %.2f s, %s)", team.agents(), set.tick,
             set.rate > 0 ? (std::to_string(set.rate) + "x real time").c_str() : "as fast as the lockstep allows");
    const auto t0 = std::chrono::steady_clock::now();
    auto speed = [&] {
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return wall > 0 ? master.last_tick_time() / wall : 0.0;
    };
    auto next_spin = std::chrono::steady_clock::now();
    bool more = true;
    while (more && ros::ok()) {
      more = master.tick(&stop);
      pub.after_tick(master, speed());
      if (std::chrono::steady_clock::now() >= next_spin) {
        ros::spinOnce();
        next_spin = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
      }
    }
    const gather::agent::RunOutcome out = master.finish();
    pub.finish(master, out.completed ? "done" : "failed", speed());
    gather::agent::RunSettings settings{set.clock == "wall" ? "lcm, wall clock" : "lcm", set.tick, set.rate, set.loss};
    gather::agent::write_mission_yaml(set.results_dir + "/mission.yaml", *plan, params, settings, out);
    if (out.oc_auth.total() > 0)
      std::printf("oc: dropped %lld fleet messages before decoding them: %s (mission.yaml: oc.rejected)\n",
                  static_cast<long long>(out.oc_auth.total()), gather::agent::describe(out.oc_auth).c_str());
    if (out.completed) {
      gather::agent::RunFiles files;
      files.add(pf, params, out);
      files.write(set.results_dir);
      std::printf(
          "oc: mission done: %s Nc=%d, %d cycles, %zu goals requested, refresh %.1f s (est. %.1f), %.2f "
          "goals per cycle (est. %.2f); %lld ticks in %.1f s = %.0fx real time -> %s\n",
          pf.method.c_str(), pf.collectors, params.cycles, out.result.goals.size(), out.result.refresh_mean_s,
          pf.est_refresh_s, out.result.goals_per_cycle, pf.est_goals, static_cast<long long>(out.ticks),
          out.wall_ms / 1000.0, out.wall_ms > 0 ? out.end_s * 1000.0 / out.wall_ms : 0.0, set.results_dir.c_str());
      for (const gather::agent::Revocation& v : out.revoked)
        std::printf("oc: %s\n", gather::agent::describe(v).c_str());
    } else {
      failure = out.failure + (ros::ok() ? "" : " (stopped)") + "; " + set.results_dir + "/mission.yaml";
    }
  } catch (const std::exception& e) {
    failure = e.what();
    try {  // the agents stop, mission.yaml and the views say so (none of it may make things worse)
      gather::agent::RunOutcome out = master.finish();
      out.completed = false;
      out.failure = failure;
      gather::agent::RunSettings settings{set.clock == "wall" ? "lcm, wall clock" : "lcm", set.tick, set.rate,
                                          set.loss};
      gather::agent::write_mission_yaml(set.results_dir + "/mission.yaml", *plan, params, settings, out);
      failure += "; " + set.results_dir + "/mission.yaml";
      pub.finish(master, "failed", 0.0);
    } catch (const std::exception&) {
    }
  }
  nh.deleteParam("/gather/plan_dir");
  if (!failure.empty()) {
    status = fail(1, failure);
    // Stopped by the user, or nobody to look at the wreck: end now (roslaunch
    // stops the launch: the OC is required). With RViz open, stay up so the
    // last picture can be looked at, until Ctrl-C.
    if (set.close_on_end || !ros::ok()) return status;
    ROS_ERROR("oc: the mission failed; its topics stay up until you stop the launch (Ctrl-C)");
    ros::spin();
    return status;
  }

  // The fleet's agents end by themselves; wait for fleet_node to say so
  // before ending the launch (it writes fleet.yaml).
  const auto wait_until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  std::string fleet;
  while (set.agents != "external" && ros::ok() && std::chrono::steady_clock::now() < wait_until &&
         !nh.getParam("/gather/fleet_status", fleet))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (set.close_on_end && gather::end_launch()) {
    ROS_INFO("oc: mission over, ending the launch (close_on_end)");
    // roslaunch stops every node now, this one included (SIGINT).
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(15);
    while (ros::ok() && std::chrono::steady_clock::now() < limit)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return status;
  }
  if (set.close_on_end) return status;  // not started by roslaunch: just end
  ROS_INFO("oc: mission over; its topics stay up until you stop the launch (Ctrl-C)");
  ros::spin();
  return status;
}
