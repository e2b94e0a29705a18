#pragma once
// The OC's ROS side of a mission: every topic a user sees (see
// mission_view.hpp and plan_markers.hpp for what each shows), published as
// the lockstep master advances. With use_sim_time it also publishes /clock
// from the mission time, so RViz and rosbag follow the mission; the stamps
// of everything it publishes are then mission time [s]. Given a bag
// instead of a node handle, it writes the same topics into the bag as
// `rosbag record` would have recorded them (mission_bag: a mission played
// back from a recording of the fleet).
#include <ros/ros.h>

#include <memory>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <rosgraph_msgs/Clock.h>

#include "gather_agent/runner/lockstep.hpp"
#include "gather_oc/mission_view.hpp"

namespace rosbag {
class Bag;  // (rosbag/bag.h needs the include paths of Debian's pluginlib: only mission_publisher.cpp has them)
}

namespace gather {

struct PublisherOptions {
  std::string frame = "map";
  bool publish_map = true;    // /map from the scenario (false: a map_server publishes it)
  bool sim_time = false;      // publish /clock; stamps are mission time
  double view_period = 0.5;   // [s] of mission time between two views (markers, TF, poses)
  double state_period = 1.0;  // [s] of mission time between two /gather/agents and /gather/status
  bool robots = false;        // the team drives robots: their footprints and headings (MissionView::show_robots)
};

// One topic of the views: published, or written into a bag at mission
// time (latched topics with the `latching` header rosbag record keeps).
template <class M>
class Outlet {
 public:
  Outlet() = default;
  Outlet(ros::NodeHandle* nh, rosbag::Bag* bag, const std::string& topic, int queue, bool latch);
  void put(const M& msg, const ros::Time& t);

 private:
  ros::Publisher pub_;
  rosbag::Bag* bag_ = nullptr;
  std::string topic_;
  boost::shared_ptr<ros::M_string> header_;
};

class MissionPublisher {
 public:
  // `map` is the scenario's map at its own resolution (published on /map).
  MissionPublisher(ros::NodeHandle& nh, const agent::TeamSetup& team, const OccupancyGrid& map,
                   const PublisherOptions& options);
  // Into `bag` (open for writing, kept open by the caller) at mission time:
  // options.sim_time is taken as true (/clock is written).
  MissionPublisher(rosbag::Bag& bag, const agent::TeamSetup& team, const OccupancyGrid& map,
                   const PublisherOptions& options);

  // Before the mission: the map, the plan's markers, the team at its start (waiting).
  void before_start(agent::LockstepMaster& master);
  // After a tick of `master` at mission time t: /clock every tick, views every view_period.
  void after_tick(agent::LockstepMaster& master, double rate);
  // The mission's last views and its status ("done" or "failed").
  void finish(agent::LockstepMaster& master, const std::string& state, double rate);

 private:
  MissionPublisher(ros::NodeHandle* nh, rosbag::Bag* bag, const agent::TeamSetup& team, const OccupancyGrid& map,
                   const PublisherOptions& options);
  ros::Time stamp(double t) const;
  void views(agent::LockstepMaster& master, double t, double rate, const std::string& state);

  const agent::TeamSetup& team_;
  const OccupancyGrid& map_;
  PublisherOptions options_;
  view::Style style_;
  view::MissionView view_;
  agent::ViewEvents events_;
  Outlet<rosgraph_msgs::Clock> clock_;
  Outlet<nav_msgs::OccupancyGrid> map_pub_;
  Outlet<visualization_msgs::MarkerArray> plan_, team_markers_, goals_, paths_;
  Outlet<tf2_msgs::TFMessage> tf_;
  Outlet<gather_msgs::AgentStates> agents_;
  Outlet<gather_msgs::MissionStatus> status_;
  Outlet<gather_msgs::CycleStats> cycles_;
  std::vector<Outlet<geometry_msgs::PoseStamped>> poses_;
  double next_view_ = 0.0, next_state_ = 0.0, last_goals_ = -1e300, last_paths_ = -1e300;
  std::size_t resolved_shown_ = 0;
  ros::Time last_tf_;
};

}  // namespace gather
