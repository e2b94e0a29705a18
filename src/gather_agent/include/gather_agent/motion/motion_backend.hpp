#pragma once
// The robot's base as a role sees it. A role decides where to go and when
// it plans to be there; the backend moves and reports the pose and the legs
// it has completed (with their arrival times). Implementations:
// - SimulatedBase: kinematics along FMM paths at the planned pace, for
//   workers in simulation (motion/simulated_base.hpp);
// - RouteFollower: a collector on its timetable (motion/route_follower.hpp);
// - a real base: drives to the waypoints with its own navigation stack and
//   reports odometry/localisation; not part of this build (gather_agent
//   --motion base says so and exits 2). docs/runtime.md describes the
//   contract a real base implements.
#include <cstddef>
#include <cstdint>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace mission {
class RouteTimetable;
}
namespace agent {

// The end of one leg: a point [m] and when the role plans to be there [s].
struct Waypoint {
  Point2 point;
  double arrive = 0.0;
};

class MotionBackend {
 public:
  virtual ~MotionBackend() = default;
  // Drives through legs[0..n) in order from `depart` [s], replacing any
  // previous plan. n <= max_legs().
  virtual void go(const Waypoint* legs, std::size_t n, double depart) = 0;
  // Stops where it is.
  virtual void hold() = 0;
  // Drives the collector route of `timetable` (a collector's whole motion).
  virtual void follow(const mission::RouteTimetable& timetable) = 0;
  // Moves on to time `now` [s] (monotonic).
  virtual void advance(double now) = 0;
  virtual Point2 pose() const = 0;                       // [m] at the last advance()
  virtual std::size_t legs_done() const = 0;             // legs of the current plan completed
  virtual double arrived_at(std::size_t leg) const = 0;  // [s] when leg `leg` was completed
  virtual std::size_t max_legs() const = 0;

  // For views (RViz): the polyline the base plans to drive, and a number
  // that changes whenever that plan changes (go, hold). Writes at most `max`
  // points to `out` (of a longer path, its first `max`) and returns how
  // many; 0: no path to show (a collector drives its plan's route).
  virtual uint32_t path_revision() const { return 0; }
  virtual std::size_t path(Point2* out, std::size_t max) const {
    (void)out, (void)max;
    return 0;
  }
};

}  // namespace agent
}  // namespace gather

namespace gather {
namespace agent {

// A base that never moves (the OC's station).
class Station : public MotionBackend {
 public:
  explicit Station(Point2 at) : pose_(at) {}
  void go(const Waypoint*, std::size_t, double) override {}
  void hold() override {}
  void follow(const mission::RouteTimetable&) override {}
  void advance(double) override {}
  Point2 pose() const override { return pose_; }
  std::size_t legs_done() const override { return 0; }
  double arrived_at(std::size_t) const override { return 0.0; }
  std::size_t max_legs() const override { return 0; }

 private:
  Point2 pose_;
};

}  // namespace agent
}  // namespace gather
