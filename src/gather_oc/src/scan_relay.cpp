#include "gather_oc/scan_relay.hpp"

#include <cmath>
#include <limits>

#include "gather_agent/transport/lcm_robot.hpp"

namespace gather {

std::string laser_frame(int agent) { return "agent_" + std::to_string(agent) + "/laser"; }

sensor_msgs::LaserScan to_laser_scan(const agent::RobotScan& s, const ros::Time& stamp) {
  sensor_msgs::LaserScan m;
  m.header.stamp = stamp;
  m.header.frame_id = laser_frame(s.agent);
  m.angle_min = s.angle_min;
  m.angle_increment = s.angle_increment;
  m.angle_max = s.angle_min + s.angle_increment * static_cast<float>(s.rays > 0 ? s.rays - 1 : 0);
  m.range_min = 0.0f;
  m.range_max = s.range_max;
  m.ranges.assign(s.ranges, s.ranges + s.rays);
  return m;
}

geometry_msgs::TransformStamped laser_transform(const agent::RobotScan& s, const std::string& map_frame,
                                                const ros::Time& stamp) {
  return view::planar_transform(map_frame, laser_frame(s.agent), stamp, s.at, s.heading);
}

visualization_msgs::Marker laser_points(const agent::RobotScan& s, const std::string& map_frame, const ros::Time& stamp,
                                        double size, const std_msgs::ColorRGBA& colour) {
  visualization_msgs::Marker m = view::marker(map_frame, stamp, "laser", s.agent, visualization_msgs::Marker::POINTS);
  m.scale.x = m.scale.y = size;
  m.color = colour;
  for (int k = 0; k < s.rays; ++k) {
    const float r = s.ranges[k];
    if (!std::isfinite(r) || r > s.range_max || r <= 0.0f) continue;
    const double a = s.heading + s.angle_min + s.angle_increment * k;
    m.points.push_back(view::pt(s.at.x + r * std::cos(a), s.at.y + r * std::sin(a), view::kZLinks));
  }
  // A lifetime: a robot whose scans stop (its world ended) leaves no stale picture.
  m.lifetime = ros::Duration(2.0);
  return m;
}

ScanRelay::ScanRelay(ros::NodeHandle& nh, const std::string& url, int agents, std::optional<agent::FleetKey> key,
                     std::string map_frame, bool sim_time, double point_size, const std_msgs::ColorRGBA& colour)
    : frame_(std::move(map_frame)), sim_time_(sim_time), point_size_(point_size), colour_(colour), newest_(agents, -1) {
  std::vector<int> ids;
  for (int a = 0; a < agents; ++a) ids.push_back(a);
  link_ = std::make_unique<agent::LcmRobotLink>(url, agent::LcmRobotLink::Side::kViewer, ids, std::move(key));
  for (int a = 0; a < agents; ++a)
    scans_.push_back(nh.advertise<sensor_msgs::LaserScan>("gather/agent_" + std::to_string(a) + "/scan", 5));
  tf_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
  markers_ = nh.advertise<visualization_msgs::MarkerArray>("gather/laser_markers", 5);
}

ScanRelay::~ScanRelay() = default;

int ScanRelay::spin_once(int timeout_ms) {
  link_->handle(timeout_ms);
  std::vector<agent::RobotScan>& got = link_->scans();
  if (got.empty()) return 0;
  std::fill(newest_.begin(), newest_.end(), -1);
  for (std::size_t i = 0; i < got.size(); ++i) {
    const int a = got[i].agent;
    if (a >= 0 && a < static_cast<int>(newest_.size())) newest_[static_cast<std::size_t>(a)] = static_cast<int>(i);
  }
  tf2_msgs::TFMessage tf;
  visualization_msgs::MarkerArray points;
  int n = 0;
  for (std::size_t a = 0; a < newest_.size(); ++a) {
    if (newest_[a] < 0) continue;
    const agent::RobotScan& s = got[static_cast<std::size_t>(newest_[a])];
    const ros::Time stamp = sim_time_ ? ros::Time(std::max(0.0, s.stamp)) : ros::Time::now();
    tf.transforms.push_back(laser_transform(s, frame_, stamp));
    scans_[a].publish(to_laser_scan(s, stamp));
    // Points in the map frame need no transform: stamped now, so a view on
    // the OC's /clock (which may trail the robots' stamps) never holds them back.
    points.markers.push_back(laser_points(s, frame_, ros::Time::now(), point_size_, colour_));
    ++n;
  }
  got.clear();
  tf_.publish(tf);
  markers_.publish(points);
  published_ += n;
  return n;
}

}  // namespace gather
