#pragma once
// The parts of a plan that executing it needs (plan.yaml holds them): where
// a worker meets its collector, a collector's closed route, the planner's
// per-worker estimate. Plain data, no planning code.
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace plan {

// Where a worker meets its collector: the route point nearest to the
// segment's entry (where the request is handed over), and every stretch of the
// route that passes next to the segment (where data can be handed over).
struct MeetingArea {
  int segment = 0;             // worker segment id
  Point2 point;                // [m] on the route, next to the segment
  double route_s = 0.0;        // [m] arc length of `point` from the route start
  std::vector<double> passes;  // [m] arc lengths of the middles of the stretches passing next to the segment
};

// A collector's closed route: from the OC through its meeting areas and back
// into the OC's coverage.
struct CollectorRoute {
  int collector = 0;              // 0..N_c-1
  std::vector<int> segments;      // worker segments it serves, in visiting order
  std::vector<Point2> waypoints;  // [m] polished, first and last at the OC
  std::vector<MeetingArea> meetings;
  double length = 0.0;            // [m]
  double period = 0.0;            // [s] length / speed
  double min_clearance = 0.0;     // [m] of the polished route
  std::vector<double> coverage_entries;  // [m] arc lengths where the route enters the OC's coverage (uploads)
};

struct WorkerEstimate {
  int segment = 0;
  int collector = -1;             // -1: delivers to the OC directly
  double expected_goals = 0.0;    // goals of one request falling in its segment
  double delivered_goals = 0.0;   // of those, measured within the cycle
  double tour_s = 0.0;            // [s] time to measure all its goals (tour + approach)
  double refresh_s = 0.0;         // [s] mean request-to-delivery time of its goals (latency)
  double interval_s = 0.0;        // [s] mean time between consecutive deliveries of its segment's data (interval)
};

}  // namespace plan
}  // namespace gather
