#pragma once
// The robots' laser scans in ROS (mission.launch laser:=true): fleet_node
// takes each robot's robot_scan_t (GATHER_ROBOT_SCAN_<k>, signed like every
// fleet message; gather_world sends them with --scans, a robot's driver
// may) and publishes
//   /gather/agent_<k>/scan   sensor_msgs/LaserScan in frame agent_<k>/laser
//   /tf                      map -> agent_<k>/laser, the laser's pose at the scan
//   /gather/laser_markers    visualization_msgs/MarkerArray: every robot's
//                            returns as points in the map frame, one
//                            RViz display for the whole team
// stamped with the scan's mission time (with /use_sim_time) or the wall clock.
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gather_agent/motion/robot_interface.hpp"
#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_oc/view_style.hpp"

namespace gather {

namespace agent {
class LcmRobotLink;
}

std::string laser_frame(int agent);  // agent_<k>/laser

// The ROS forms of a scan (pure: tested without a master).
sensor_msgs::LaserScan to_laser_scan(const agent::RobotScan& scan, const ros::Time& stamp);
geometry_msgs::TransformStamped laser_transform(const agent::RobotScan& scan, const std::string& map_frame,
                                                const ros::Time& stamp);
// Its returns (finite ranges up to range_max) as a POINTS marker in the map
// frame, namespace "laser", id the agent's; `size` [m] per point.
visualization_msgs::Marker laser_points(const agent::RobotScan& scan, const std::string& map_frame,
                                        const ros::Time& stamp, double size, const std_msgs::ColorRGBA& colour);

class ScanRelay {
 public:
  // Listens on `url` ("" LCM's default) for the scans of agents 0 .. agents-1;
  // `point_size` [m] and `colour`: the markers' points (the view's
  // Style::laser). Throws gather::Error when LCM cannot open the URL.
  ScanRelay(ros::NodeHandle& nh, const std::string& url, int agents, std::optional<agent::FleetKey> key,
            std::string map_frame, bool sim_time, double point_size, const std_msgs::ColorRGBA& colour);
  ~ScanRelay();
  ScanRelay(const ScanRelay&) = delete;
  ScanRelay& operator=(const ScanRelay&) = delete;

  // Takes what arrived within `timeout_ms` and publishes the newest scan of
  // each robot; returns how many it published.
  int spin_once(int timeout_ms);
  int64_t published() const { return published_; }

 private:
  std::unique_ptr<agent::LcmRobotLink> link_;
  std::vector<ros::Publisher> scans_;
  ros::Publisher tf_, markers_;
  std::string frame_;
  bool sim_time_;
  double point_size_;
  std_msgs::ColorRGBA colour_;
  std::vector<int> newest_;  // per agent: index into the link's scans, -1
  int64_t published_ = 0;
};

}  // namespace gather
