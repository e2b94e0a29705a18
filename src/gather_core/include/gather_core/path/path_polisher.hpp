#pragma once
// The final details of a path: shortcuts and smoothing of an FMM path, with
// OMPL's B-spline smoothing, keeping a robot's clearance everywhere.
#include <vector>

#include "gather_core/grid/clearance.hpp"

namespace gather {

struct PolishOptions {
  double robot_radius = 0.2;      // [m] every point of the result keeps this distance from blocked cells
  double check_step = 0.0;        // [m] spacing of clearance checks along segments; 0 = resolution / 2
  unsigned smoothing_passes = 3;  // OMPL PathSimplifier::smoothBSpline steps; 0 = shortcuts only
  double min_spacing = 0.25;      // [m] smoothed vertices closer than this to the previous kept one are dropped
};

struct PolishedPath {
  std::vector<Point2> points;  // [m], first and last equal the input's
  double length = 0.0;         // [m]
  double min_clearance = 0.0;  // [m] smallest free_distance along the result (checked every check_step)
};

// Deterministic: greedy shortcuts (from each kept point, a far later point
// reachable by a straight segment that keeps the clearance, found by
// galloping and bisection), then
// OMPL B-spline smoothing, which only accepts clearance-keeping changes.
// Stretches of the input that already violate the clearance (a doorway
// narrower than the robot) are kept as they are; min_clearance reports it.
// Throws gather::Error if `path` is empty.
PolishedPath polish_path(const std::vector<Point2>& path, const ClearanceMap& clearance,
                         const PolishOptions& options = {});

}  // namespace gather
