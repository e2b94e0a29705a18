#pragma once
// A collector's closed route as a function of time: it leaves the OC at t = 0
// and drives the polyline at constant speed, its loops synchronised with the
// OC's requests (plan::LoopSchedule: a loop starts when a request is issued;
// between loops it waits at the OC). Motion is analytic, so where the
// collector is at any time, when it next passes an arc position and when it is
// next inside the OC's radio coverage are exact (coverage borders are found by
// bisection along the route to 1e-6 m).
#include <cstdint>
#include <utility>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/plan/loop_schedule.hpp"
#include "gather_core/plan/plan_types.hpp"

namespace gather {
namespace mission {

class RouteTimetable {
 public:
  // `coverage`: the cells inside the OC's coverage, in the grid's frame.
  // speed [m/s] > 0, request_period [s] > 0 (the OC's T). A route of fewer
  // than two waypoints or zero length is idle (it never moves and is never
  // met).
  RouteTimetable(const plan::CollectorRoute& route, double speed, double request_period, const Mask& coverage);

  bool idle() const { return length_ <= 0.0; }
  double length() const { return length_; }                          // [m]
  double speed() const { return speed_; }                            // [m/s]
  double period() const { return idle() ? 0.0 : length_ / speed_; }  // [s] one loop's driving time
  const plan::LoopSchedule& schedule() const { return schedule_; }
  const std::vector<Point2>& waypoints() const { return points_; }  // [m] the closed polyline, OC to OC
  const std::vector<double>& arcs() const { return arc_; }          // [m] arc position of each waypoint
  Point2 position_at_arc(double s) const;                           // s in [0, length] [m]
  Point2 position(double t) const;                                  // at time t [s]
  // Earliest time >= t [s] at which the collector is at arc position s [m]
  // (t is compared with a 1 ms tolerance, so a worker on time up to float
  // rounding of its FMM distances meets it).
  double next_time_at(double s, double t) const;
  // Earliest time >= t [s] at which the collector is inside the coverage.
  double next_coverage_time(double t) const;
  // Arc intervals [m] of one loop inside the coverage, ascending.
  const std::vector<std::pair<double, double>>& coverage_intervals() const { return inside_; }

 private:
  std::vector<Point2> points_;
  std::vector<double> arc_;  // cumulative [m]
  double speed_ = 1.0;
  double length_ = 0.0;
  plan::LoopSchedule schedule_{0.0, 1.0};
  std::vector<std::pair<double, double>> inside_;
};

}  // namespace mission
}  // namespace gather
