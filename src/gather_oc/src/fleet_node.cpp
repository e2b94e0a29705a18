// fleet_node: starts one gather_agent process per agent of the plan (N comes
// from the plan, not from a hand-written node list) once the OC has
// published where the plan is (/gather/plan_dir), reports agents that
// fail, and on shutdown stops those still running and writes
// `~results_dir/fleet.yaml`. Agents end by themselves (exit 0) when the OC
// ends the mission; an agent of ~kill (mission.launch's kill:=) that the OC
// ended with SIGKILL is no failure, and one of ~restart (restart:=) that
// the OC ended with SIGKILL is started again (respawn) with --rejoin: it
// replays its journal (results_dir/journal) and joins the mission. The
// agents not running are on /gather/fleet/ended (latched, kept up until the
// launch ends): the OC stops at once when one it waits on has ended. On
// robots with ~laser (mission.launch laser:=true) it starts gather_world
// with --scans and relays every robot's scan to ROS (gather_oc/scan_relay.hpp). Exit status: 0 every agent exited 0
// within 1 s of its stop (or was killed as asked), 1 otherwise, 2 bad input.
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "gather_agent/runner/agent_fleet.hpp"
#include "gather_agent/runner/agent_keys.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_msgs/FleetEnded.h"
#include "gather_oc/launch_paths.hpp"
#include "gather_oc/scan_relay.hpp"
#include "gather_oc/view_style.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// Agents the OC kills (~kill) end with SIGKILL: as asked.
bool killed_as_asked(const gather::AgentProcess& a, const std::vector<gather::agent::Kill>& kills) {
  if (a.exit_status != 128 + SIGKILL) return false;
  for (const gather::agent::Kill& k : kills)
    if (k.agent == a.id) return true;
  return false;
}

void write_fleet_results(const std::string& path, const gather::AgentFleet& fleet, bool ok,
                         const std::vector<gather::agent::Kill>& kills) {
  YAML::Emitter y;
  y.SetDoublePrecision(6);
  y << YAML::BeginMap << YAML::Key << "status" << YAML::Value << (ok ? "ok" : "failed");
  y << YAML::Key << "agents" << YAML::Value << YAML::BeginSeq;
  for (const auto& a : fleet.agents()) {
    // exited_early: ended by itself (at the mission's end, or on an error:
    // see exit_status); otherwise stopped with SIGTERM after stop_latency_s.
    y << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << a.id << YAML::Key << "exit_status"
      << YAML::Value << a.exit_status << YAML::Key << "ended" << YAML::Value
      << (a.exited_early ? "by_itself" : "stopped") << YAML::Key << "stop_latency_s" << YAML::Value << a.stop_latency_s
      << YAML::Key << "killed_as_asked" << YAML::Value << killed_as_asked(a, kills) << YAML::Key << "restarts"
      << YAML::Value << a.restarts << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
  std::ofstream out(path);
  out << y.c_str() << "\n";
  if (!out) std::fprintf(stderr, "fleet: %s: cannot write results file\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // a line at a time, also into a log file or a pipe
  ros::init(argc, argv, "fleet", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::vector<std::string> all, args;
  ros::removeROSArgs(argc, argv, all);
  bool map_from_topic = false;
  for (std::size_t i = 1; i < all.size(); ++i) {
    if (all[i].rfind("--map-topic=", 0) == 0)
      map_from_topic = all[i].size() > 12 && all[i].substr(12) != "none";
    else
      args.push_back(all[i]);
  }
  if (args.size() != 1) {
    std::fprintf(stderr, "fleet: usage: fleet_node SCENARIO [--map-topic=TOPIC] (settings as private parameters)\n");
    return 2;
  }
  const std::string scenario_path = gather::resolve_launch_path(args[0]);
  int agents = 0;
  try {
    // With the map from a topic the scenario may have none: the team is all
    // it needs. "auto" (mission.launch's default): the plan's, checked by the OC.
    if (args[0] != "auto")
      agents =
          (map_from_topic ? gather::load_scenario_settings(scenario_path, false) : gather::load_scenario(scenario_path))
              .team.agents;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fleet: %s\n", e.what());
    return 2;
  }
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string lcm_url, reply_url, agent_bin, results_dir, kill, restart, robots, world_bin, world_config;
  double plan_timeout = 300.0, scan_rate = 2.0;
  bool laser = false;
  pnh.param<std::string>("lcm_url", lcm_url, "");
  pnh.param<std::string>("reply_url", reply_url, "");
  pnh.param<std::string>("agent_bin", agent_bin, "");
  pnh.param<std::string>("results_dir", results_dir, "");
  pnh.param<std::string>("kill", kill, "none");
  pnh.param<std::string>("restart", restart, "none");
  pnh.param("plan_timeout", plan_timeout, 300.0);
  pnh.param<std::string>("robots", robots, "ideal");
  pnh.param<std::string>("world_bin", world_bin, "auto");
  pnh.param<std::string>("world_config", world_config, "");
  pnh.param("laser", laser, false);
  pnh.param("scan_rate", scan_rate, 2.0);
  if (robots != "ideal" && robots != "mrpt" && robots != "external") {
    std::fprintf(stderr, "fleet: ~robots must be ideal, mrpt or external, got '%s'\n", robots.substr(0, 40).c_str());
    return 2;
  }
  if (laser && robots == "ideal") {
    std::fprintf(stderr, "fleet: ~laser needs robots (robots:=mrpt or external): ideal bases have no laser\n");
    return 2;
  }
  if (!(scan_rate > 0 && scan_rate <= 50)) {
    std::fprintf(stderr, "fleet: ~scan_rate must be in (0, 50] Hz of mission time, got %g\n", scan_rate);
    return 2;
  }
  if (world_bin == "auto") world_bin.clear();
  if (world_config == "none") world_config.clear();
  world_config = world_config.empty() ? "" : gather::resolve_launch_path(world_config);
  if (lcm_url == "default") lcm_url.clear();  // mission.launch's "not given"
  // The URL the OC opens, given to every process it starts (an agent with
  // --motion lcm would take the robots' default otherwise).
  lcm_url = gather::agent::effective_url(lcm_url);
  if (agent_bin == "auto") agent_bin.clear();
  results_dir = gather::resolve_launch_path(results_dir);
  const std::string bin = gather::find_agent_binary(agent_bin);
  if (bin.empty()) {
    std::fprintf(stderr, "fleet: gather_agent binary not found (%s)\n",
                 agent_bin.empty() ? "searched CMAKE_PREFIX_PATH/lib/gather_agent and PATH; source the workspace"
                                   : ("~agent_bin " + agent_bin + " is not executable").c_str());
    return 2;
  }

  // The OC plans first (or checks the given plan), then says where it is.
  std::string plan_dir;
  const ros::WallTime t0 = ros::WallTime::now();
  while (!g_stop && ros::ok() && !nh.getParam("/gather/plan_dir", plan_dir)) {
    if ((ros::WallTime::now() - t0).toSec() > plan_timeout) {
      std::fprintf(stderr, "fleet: the OC did not publish /gather/plan_dir within %.0f s\n", plan_timeout);
      return 1;
    }
    ros::WallDuration(0.05).sleep();
  }
  if (g_stop || !ros::ok()) return 0;

  // The team is the plan's (the OC checked it against the scenario).
  try {
    agents = static_cast<int>(gather::plan::read_plan_file(plan_dir + "/plan.yaml").agents.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fleet: %s\n", e.what());
    return 1;
  }
  std::vector<gather::agent::Kill> kills, restarts;
  try {
    kills = gather::agent::parse_kills(kill, agents, "~kill");
    restarts = gather::agent::parse_kills(restart, agents, "~restart");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fleet: %s\n", e.what());
    return 2;
  }
  // The OC's fleet key (or --insecure), set with the plan's directory.
  std::string key_file;
  if (!nh.getParam("/gather/key_file", key_file)) {
    std::fprintf(stderr,
                 "fleet: the OC did not say which fleet key to use (/gather/key_file): not starting unsigned agents\n");
    return 1;
  }
  std::vector<std::string> command{bin, "--id", "{id}", "--plan", plan_dir};
  if (key_file.empty()) {
    command.push_back("--insecure");
  } else {
    // Each agent its own keys, from the OC's master (docs/security.md).
    const std::string keys_dir = (results_dir.empty() ? std::string(".") : results_dir) + "/keys";
    try {
      gather::agent::write_agent_keys(gather::agent::load_fleet_key(key_file),
                                      gather::plan::read_plan_file(plan_dir + "/plan.yaml"), keys_dir);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "fleet: %s\n", e.what());
      return 1;
    }
    command.insert(command.end(), {"--key-file", keys_dir + "/agent-{id}.key"});
  }
  if (!lcm_url.empty()) command.insert(command.end(), {"--lcm-url", lcm_url});
  if (!restarts.empty())
    command.insert(command.end(), {"--journal", (results_dir.empty() ? "." : results_dir) + "/journal"});
  const std::string replies = reply_url.empty() ? gather::agent::LcmFleet::reply_url_for(lcm_url) : reply_url;
  command.insert(command.end(), {"--reply-url", replies});
  if (robots != "ideal") command.insert(command.end(), {"--motion", "lcm"});
  // On gather_world's robots: gather_world beside the agents, on the same LCM.
  std::unique_ptr<gather::AgentFleet> world;
  if (robots == "mrpt") {
    const std::string wbin = gather::find_world_binary(world_bin);
    if (wbin.empty()) {
      std::fprintf(stderr, "fleet: gather_world binary not found (%s)\n",
                   world_bin.empty() ? "searched CMAKE_PREFIX_PATH/lib/gather_world and PATH; source the workspace"
                                     : ("~world_bin " + world_bin + " is not executable").c_str());
      return 2;
    }
    std::vector<std::string> w{wbin, "--plan", plan_dir, "--reply-url", replies};
    if (key_file.empty())
      w.push_back("--insecure");
    else
      w.insert(w.end(), {"--key-file", key_file});
    if (!lcm_url.empty()) w.insert(w.end(), {"--lcm-url", lcm_url});
    if (!world_config.empty()) w.insert(w.end(), {"--config", world_config});
    if (laser) w.insert(w.end(), {"--scans", std::to_string(scan_rate)});
    world = std::make_unique<gather::AgentFleet>(w, 1);
    try {
      world->start();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "fleet: %s\n", e.what());
      return 1;
    }
    ROS_INFO("fleet: started gather_world (%s) for %d robots", wbin.c_str(), agents);
  }
  // The robots' scans in ROS, points as large as the view's other marks.
  std::unique_ptr<gather::ScanRelay> relay;
  if (laser) {
    try {
      const gather::plan::PlanFile pf = gather::plan::read_plan_file(plan_dir + "/plan.yaml");
      const gather::view::Style style(gather::load_scenario(pf.scenario).grid);
      bool sim_time = false;
      nh.param("/use_sim_time", sim_time, false);
      std::string frame;
      nh.param<std::string>("/oc/frame_id", frame, "map");
      relay = std::make_unique<gather::ScanRelay>(
          nh, lcm_url, agents, gather::agent::robot_key_from_options(key_file, key_file.empty(), "fleet"), frame,
          sim_time, 0.35 * style.unit, style.laser);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "fleet: ~laser: %s\n", e.what());
      return 1;
    }
    ROS_INFO("fleet: relaying the robots' laser scans to /gather/agent_<k>/scan and /gather/laser_markers");
  }
  gather::AgentFleet fleet(command, agents);
  try {
    fleet.start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fleet: %s\n", e.what());
    return 1;
  }
  ROS_INFO("fleet: started %d agents (%s --plan %s)", agents, bin.c_str(), plan_dir.c_str());

  // Which agent processes are not running, for the OC (latched): it stops
  // the mission when one it waits on has ended, naming its exit status,
  // instead of waiting out its timeout.
  ros::Publisher ended_pub = nh.advertise<gather_msgs::FleetEnded>("/gather/fleet/ended", 1, true);
  gather_msgs::FleetEnded ended;
  auto publish_ended = [&] {
    gather_msgs::FleetEnded now;
    for (const gather::AgentProcess& p : fleet.agents())
      if (!p.running) now.agents.push_back(static_cast<int16_t>(p.id)), now.exit_status.push_back(p.exit_status);
    if (now.agents != ended.agents || now.exit_status != ended.exit_status) {
      ended = now;
      ended_pub.publish(ended);
    }
  };
  ended_pub.publish(ended);

  bool ok = true;
  int done = 0;
  while (!g_stop && ros::ok() && done < agents) {
    const std::vector<int> just_ended = fleet.poll();
    for (int id : just_ended) {
      ++done;
      const int status = fleet.agents()[static_cast<std::size_t>(id)].exit_status;
      const gather::AgentProcess& p = fleet.agents()[static_cast<std::size_t>(id)];
      if (p.exit_status == 128 + SIGKILL && p.restarts == 0 && killed_as_asked(p, restarts)) {
        --done;
        try {
          fleet.respawn(id, {"--rejoin"});
          ROS_WARN("fleet: agent %d killed (SIGKILL) and started again from its journal (~restart)", id);
        } catch (const std::exception& e) {
          ok = false;
          ++done;
          ROS_ERROR("fleet: agent %d: %s", id, e.what());
        }
      } else if (killed_as_asked(p, kills)) {
        ROS_WARN("fleet: agent %d killed (SIGKILL) as asked (~kill)", id);
      } else if (status != 0) {
        ok = false;
        ROS_ERROR("fleet: agent %d ended with status %d", id, status);
      }
    }
    if (!just_ended.empty()) publish_ended();
    if (relay)
      relay->spin_once(50);
    else
      ros::WallDuration(0.05).sleep();
  }
  fleet.stop(2.0);
  if (world) {
    world->wait(5.0);
    world->stop(2.0);
    const int status = world->agents()[0].exit_status;
    if (status != 0) {
      ok = false;
      ROS_ERROR("fleet: gather_world ended with status %d", status);
    }
  }
  int slow = 0;
  for (const auto& a : fleet.agents()) {
    if (a.exit_status != 0 && !killed_as_asked(a, kills)) ok = false;
    if (!a.exited_early && a.stop_latency_s > 1.0) ok = false, ++slow;
  }
  if (!results_dir.empty()) write_fleet_results(results_dir + "/fleet.yaml", fleet, ok, kills);
  nh.setParam("/gather/fleet_status", ok ? "ok" : "failed");  // the OC ends the launch once it is there
  std::printf("fleet: %d agents: %s%s\n", agents, ok ? "all exited 0" : "FAILURES (see fleet.yaml)",
              slow ? (", " + std::to_string(slow) + " took > 1 s to stop").c_str() : "");
  std::fflush(stdout);
  // /gather/fleet/ended is latched, but only while this node lives: the OC
  // may not have read that its agents ended yet. Stay until the launch ends
  // (the OC ends it when the mission is over or has failed).
  while (!g_stop && ros::ok()) ros::WallDuration(0.1).sleep();
  ros::shutdown();
  return ok ? 0 : 1;
}
