#include "gather_oc/view_style.hpp"

#include <algorithm>
#include <cmath>

namespace gather {
namespace view {

std_msgs::ColorRGBA rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r, c.g = g, c.b = b, c.a = a;
  return c;
}

std_msgs::ColorRGBA rgba(figures::Rgb c, float a) { return rgba(c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, a); }

Style::Style(const OccupancyGrid& map) {
  const double side = std::max(map.width(), map.height()) * map.resolution();
  unit = std::clamp(side / 90.0, 0.15, 5.0);
}

std_msgs::ColorRGBA Style::collector(CollectorId collector, float a) const {
  const auto& p = figures::collector_palette();
  return rgba(p[static_cast<std::size_t>(std::max(collector.value(), 0)) % p.size()], a);
}

Box reachable_box(const Mask& reachable) {
  const GridFrame& f = reachable.frame();
  int c0 = f.width, c1 = -1, r0 = f.height, r1 = -1;
  for (int r = 0; r < f.height; ++r)
    for (int c = 0; c < f.width; ++c)
      if (reachable.at(Cell{r, c}))
        c0 = std::min(c0, c), c1 = std::max(c1, c), r0 = std::min(r0, r), r1 = std::max(r1, r);
  if (c1 < 0) c0 = 0, c1 = f.width - 1, r0 = 0, r1 = f.height - 1;
  const double res = f.resolution;
  return Box{f.origin.x + c0 * res, f.origin.y + r0 * res, f.origin.x + (c1 + 1) * res, f.origin.y + (r1 + 1) * res};
}

geometry_msgs::Point pt(double x, double y, double z) {
  geometry_msgs::Point q;
  q.x = x, q.y = y, q.z = z;
  return q;
}

geometry_msgs::Point pt(Point2 p, double z) { return pt(p.x, p.y, z); }

geometry_msgs::TransformStamped planar_transform(const std::string& frame, const std::string& child,
                                                 const ros::Time& stamp, Point2 at, double yaw) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = frame;
  t.header.stamp = stamp;
  t.child_frame_id = child;
  t.transform.translation.x = at.x;
  t.transform.translation.y = at.y;
  t.transform.rotation.z = std::sin(yaw / 2);
  t.transform.rotation.w = std::cos(yaw / 2);
  return t;
}

visualization_msgs::Marker marker(const std::string& frame, const ros::Time& stamp, const std::string& ns, int id,
                                  int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color = rgba(1.0f, 1.0f, 1.0f);
  return m;
}

}  // namespace view
}  // namespace gather
