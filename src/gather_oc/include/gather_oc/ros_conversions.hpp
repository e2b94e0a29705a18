#pragma once
// gather_core / gather_agent data as ROS messages.
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// The grid as nav_msgs/OccupancyGrid in frame `frame` (same cell order and values).
nav_msgs::OccupancyGrid to_map_msg(const OccupancyGrid& grid, const std::string& frame, const ros::Time& stamp);

// RViz markers: the OC (red cube) and every agent (its pose from its last
// tick reply; spheres: blue workers, black collectors, orange before the
// mission starts) with its id, in frame `frame`.
visualization_msgs::MarkerArray team_markers(Point2 oc, const std::vector<agent::Reply>& agents,
                                             const std::string& frame, const ros::Time& stamp, bool started);

}  // namespace gather
