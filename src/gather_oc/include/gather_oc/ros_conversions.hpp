#pragma once
// gather_core grids as nav_msgs/OccupancyGrid and back.
#include <nav_msgs/OccupancyGrid.h>

#include <string>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// The grid as nav_msgs/OccupancyGrid in frame `frame` (same cell order and values).
nav_msgs::OccupancyGrid to_map_msg(const OccupancyGrid& grid, const std::string& frame, const ros::Time& stamp);

// A map message as a grid: values as they are, free where the value is 0
// (map_server's free cells in every mode but raw). Throws gather::Error
// naming `topic` when the message is not a usable map (empty, a size that
// does not match its data, resolution <= 0, a rotated origin, non-finite
// numbers).
OccupancyGrid from_map_msg(const nav_msgs::OccupancyGrid& msg, const std::string& topic);

}  // namespace gather
