#pragma once
// Where the team stands at the start: all agents close to the OC (seed, sec. 3).
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// [m] how far apart the team stands at the start.
constexpr double kStartSpacing = 0.6;

// Start positions [m] of agents 0..n-1: free cells reachable from the OC,
// taken in breadth-first order from the OC cell so they are as close to it as
// the map allows, at least `spacing` [m] apart, from the OC itself and from
// the positions already `taken` (agents placed elsewhere). Deterministic.
// Throws gather::Error if the reachable free space cannot hold n.
std::vector<Point2> start_poses(const OccupancyGrid& grid, Point2 oc, int n, double spacing = kStartSpacing,
                                const std::vector<Point2>& taken = {});

}  // namespace gather
