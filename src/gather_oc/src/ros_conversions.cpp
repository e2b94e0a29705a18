#include "gather_oc/ros_conversions.hpp"

#include <charconv>
#include <cmath>

#include "gather_core/error.hpp"

namespace gather {

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

OccupancyGrid from_map_msg(const nav_msgs::OccupancyGrid& msg, const std::string& topic) {
  const auto& i = msg.info;
  if (i.width == 0 || i.height == 0 || i.width > 100000 || i.height > 100000)
    throw Error(topic, "map of " + std::to_string(i.width) + " x " + std::to_string(i.height) + " cells");
  if (msg.data.size() != static_cast<std::size_t>(i.width) * i.height)
    throw Error(topic, "map data holds " + std::to_string(msg.data.size()) + " cells, not " + std::to_string(i.width) +
                           " x " + std::to_string(i.height));
  if (!(i.resolution > 0.0f) || !std::isfinite(i.resolution))
    throw Error(topic, "map resolution must be > 0 m/cell, got " + std::to_string(i.resolution));
  const auto& q = i.origin.orientation;
  if (!std::isfinite(i.origin.position.x) || !std::isfinite(i.origin.position.y))
    throw Error(topic, "map origin is not a finite position");
  if (std::abs(q.x) > 1e-6 || std::abs(q.y) > 1e-6 || std::abs(q.z) > 1e-6)
    throw Error(topic, "map origin is rotated; only maps whose origin has yaw 0 are supported");
  std::vector<int8_t> values(msg.data.begin(), msg.data.end());
  std::vector<uint8_t> free(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) free[k] = values[k] == 0;
  // nav_msgs keeps the resolution as float32: take the shortest decimal that
  // rounds to it (0.05f -> 0.05, as the map's YAML said), not its binary
  // value (0.0500000007...), so a map from a topic is the map of its file.
  char text[32];
  const auto r = std::to_chars(text, text + sizeof text, i.resolution);
  double resolution = i.resolution;
  if (r.ec == std::errc()) std::from_chars(text, r.ptr, resolution);
  return OccupancyGrid(static_cast<int>(i.width), static_cast<int>(i.height), resolution,
                       Point2{i.origin.position.x, i.origin.position.y}, std::move(values), std::move(free));
}

}  // namespace gather
