#include "gather_oc/ros_conversions.hpp"

namespace gather {
namespace {

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r, c.g = g, c.b = b, c.a = a;
  return c;
}


}  // namespace

nav_msgs::OccupancyGrid to_map_msg(const OccupancyGrid& grid, const std::string& frame, const ros::Time& stamp) {
  nav_msgs::OccupancyGrid m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.info.map_load_time = stamp;
  m.info.resolution = static_cast<float>(grid.resolution());
  m.info.width = static_cast<uint32_t>(grid.width());
  m.info.height = static_cast<uint32_t>(grid.height());
  m.info.origin.position.x = grid.origin().x;
  m.info.origin.position.y = grid.origin().y;
  m.info.origin.orientation.w = 1.0;
  m.data.assign(grid.values().begin(), grid.values().end());
  return m;
}

visualization_msgs::MarkerArray team_markers(Point2 oc, const std::vector<agent::Reply>& agents,
                                             const std::string& frame, const ros::Time& stamp, bool started) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker base;
  base.header.frame_id = frame;
  base.header.stamp = stamp;
  base.action = visualization_msgs::Marker::ADD;
  base.pose.orientation.w = 1.0;

  visualization_msgs::Marker m = base;
  m.ns = "oc";
  m.id = 0;
  m.type = visualization_msgs::Marker::CUBE;
  m.pose.position.x = oc.x;
  m.pose.position.y = oc.y;
  m.pose.position.z = 0.3;
  m.scale.x = m.scale.y = m.scale.z = 0.6;
  m.color = rgba(0.85f, 0.1f, 0.1f);
  out.markers.push_back(m);

  for (const agent::Reply& a : agents) {
    visualization_msgs::Marker s = base;
    s.ns = "agents";
    s.id = a.agent;
    s.type = visualization_msgs::Marker::SPHERE;
    s.pose.position.x = a.pose.x;
    s.pose.position.y = a.pose.y;
    s.pose.position.z = 0.2;
    s.scale.x = s.scale.y = s.scale.z = 0.4;
    s.color = !started ? rgba(1.0f, 0.55f, 0.0f)
                       : a.role == agent::RoleKind::kCollector ? rgba(0.1f, 0.1f, 0.1f) : rgba(0.15f, 0.35f, 0.9f);
    out.markers.push_back(s);

    visualization_msgs::Marker t = base;
    t.ns = "agent_ids";
    t.id = a.agent;
    t.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    t.text = std::to_string(a.agent);
    t.pose.position.x = a.pose.x;
    t.pose.position.y = a.pose.y + 0.4;
    t.pose.position.z = 0.5;
    t.scale.z = 0.35;
    t.color = rgba(0.1f, 0.1f, 0.1f);
    out.markers.push_back(t);
  }
  return out;
}

}  // namespace gather
