// oc_node: the Operation Center. Loads the scenario, publishes /map (latched)
// and RViz markers, listens to the agents over LCM, and after `~duration`
// seconds writes `~results_dir/mission.yaml` and a summary line.
// Exit status: 0 all agents heard, 1 some never heard, 2 bad input.
#include <ros/ros.h>

#include <chrono>
#include <cstdio>

#include "gather_agent/fleet_monitor.hpp"
#include "gather_agent/lcm_open.hpp"
#include "gather_core/error.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_oc/launch_paths.hpp"
#include "gather_oc/mission_results.hpp"
#include "gather_oc/ros_conversions.hpp"

namespace {

struct StateHandler {
  gather::FleetMonitor* fleet;
  double now_s = 0.0;
  void on_state(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    fleet->on_message(rbuf->data, static_cast<int>(rbuf->data_size), now_s);
  }
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "oc");
  // The scenario is the one positional argument and is loaded before the node
  // talks to the ROS master, so bad input fails fast with one line.
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 2) {
    std::fprintf(stderr, "oc_node: usage: oc_node SCENARIO (settings as private parameters ~duration, ~results_dir, ~lcm_url)\n");
    return 2;
  }
  const std::string scenario_path = gather::resolve_launch_path(args[1]);
  gather::Scenario scenario;
  try {
    scenario = gather::load_scenario(scenario_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "oc_node: %s\n", e.what());
    return 2;
  }
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::string lcm_url, results_dir;
  double duration_s = 0.0, marker_hz = 2.0;
  pnh.param<std::string>("lcm_url", lcm_url, "");
  pnh.param<std::string>("results_dir", results_dir, "");
  results_dir = gather::resolve_launch_path(results_dir);
  pnh.param("duration", duration_s, 0.0);
  pnh.param("marker_rate", marker_hz, 2.0);
    if (!(duration_s >= 0.0) || !(marker_hz > 0.0)) {
    std::fprintf(stderr, "oc_node: ~duration must be >= 0 s and ~marker_rate > 0 Hz\n");
    return 2;
  }
  std::string lcm_error;
  auto lcm = gather::open_lcm(lcm_url, &lcm_error);
  if (!lcm) {
    std::fprintf(stderr, "oc_node: %s\n", lcm_error.c_str());
    return 2;
  }

  gather::FleetMonitor fleet(scenario.team.agents);
  StateHandler handler{&fleet};
  lcm->subscribe(gather::kAgentStateChannel, &StateHandler::on_state, &handler);

  ros::Publisher map_pub = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, /*latch=*/true);
  ros::Publisher marker_pub = nh.advertise<visualization_msgs::MarkerArray>("gather/markers", 1, /*latch=*/true);
  map_pub.publish(gather::to_map_msg(scenario.grid, "map", ros::Time::now()));
  ROS_INFO("oc: scenario %s, map %dx%d at %.3f m/cell, expecting %d agents%s", scenario.path.c_str(),
           scenario.grid.width(), scenario.grid.height(), scenario.grid.resolution(), scenario.team.agents,
           duration_s > 0 ? (", mission of " + std::to_string(duration_s) + " s").c_str() : "");

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const double marker_period = 1.0 / marker_hz;
  double next_marker = 0.0;
  double elapsed = 0.0;
  while (ros::ok()) {
    lcm->handleTimeout(20);
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    handler.now_s = elapsed;
    ros::spinOnce();
    if (elapsed >= next_marker) {
      marker_pub.publish(gather::team_markers(scenario.oc, fleet.agents(), "map", ros::Time::now(), elapsed,
                                              3.0 * marker_period + 1.0));
      next_marker += marker_period;
    }
    if (duration_s > 0.0 && elapsed >= duration_s) break;
  }

  const gather::MissionSummary summary = gather::summarize(fleet, elapsed);
  std::string results_file;
  if (!results_dir.empty()) {
    results_file = results_dir + "/mission.yaml";
    try {
      gather::write_mission_results(results_file, scenario, fleet, summary);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "oc_node: %s\n", e.what());
      return 1;
    }
  }
  std::printf("oc: mission %s after %.1f s: %d/%d agents heard, %lld heartbeats, %lld missed, %lld rejected%s%s\n",
              summary.ok() ? "done" : "INCOMPLETE", summary.duration_s, summary.agents_heard,
              summary.agents_expected, summary.heartbeats, summary.missed, summary.rejected,
              results_file.empty() ? "" : " -> ", results_file.c_str());
  std::fflush(stdout);
  return summary.ok() ? 0 : 1;
}
