#pragma once
// gather_core / gather_agent data as ROS messages.
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include "gather_agent/fleet_monitor.hpp"
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// The grid as nav_msgs/OccupancyGrid in frame `frame` (same cell order and values).
nav_msgs::OccupancyGrid to_map_msg(const OccupancyGrid& grid, const std::string& frame, const ros::Time& stamp);

// RViz markers: the OC (red cube) and every agent heard so far (sphere coloured
// by role, with its id), in frame `frame`. `now_s` and `stale_after_s` grey out
// agents whose last heartbeat is old.
visualization_msgs::MarkerArray team_markers(Point2 oc, const std::vector<AgentRecord>& agents,
                                             const std::string& frame, const ros::Time& stamp, double now_s,
                                             double stale_after_s);

}  // namespace gather
