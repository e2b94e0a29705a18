#pragma once
// The ideal collector base: it drives what it is commanded at the planned
// pace, straight from waypoint to waypoint (a collector route's waypoints
// are a polished, collision-free path already), and reaches every waypoint
// at its planned time. A command that is a loop of its route on the route's
// timetable (the waypoints of the route from some vertex on, each at the
// timetable's time there) puts it where the timetable's closed form says
// (mission::RouteTimetable::position), bit for bit: so an ideal collector
// is where the analytic simulator's collector is, and the equivalence checks
// (agents vs simulator, docs/runtime_equivalence.md) stay exact. It never
// fails, is never blocked and never late.
#include <vector>

#include "gather_agent/motion/motion_backend.hpp"
#include "gather_core/mission/route_timetable.hpp"

namespace gather {
namespace agent {

class RouteBase : public MotionBackend {
 public:
  // `route` must outlive the base. Room for `max_legs` waypoints a command.
  RouteBase(const mission::RouteTimetable& route, Point2 start, std::size_t max_legs);

  void go(const Waypoint* legs, std::size_t n, double now) override;
  void stop(double now) override;
  void update(double now) override;
  Point2 pose() const override { return pose_; }
  double heading() const override { return heading_; }
  double speed() const override { return speed_now_; }
  NavState state() const override {
    return n_ == 0 ? NavState::kIdle : done_ < n_ ? NavState::kActive : NavState::kReached;
  }
  std::size_t legs_done() const override { return done_; }
  double arrived_at(std::size_t leg) const override { return legs_[leg].arrive; }
  double arrival_estimate() const override { return n_ > 0 ? legs_[n_ - 1].arrive : kNoEstimate; }
  std::size_t max_legs() const override { return legs_.size(); }

  // True while the current command keeps the timetable (tests).
  bool on_timetable() const { return on_timetable_; }

 private:
  bool keeps_timetable(const Waypoint* legs, std::size_t n) const;

  const mission::RouteTimetable& route_;
  std::vector<Waypoint> legs_;
  std::size_t n_ = 0, done_ = 0;
  Point2 from_;  // [m] where the current command started
  double depart_ = 0.0;
  bool on_timetable_ = false;
  double loop_depart_ = 0.0;  // [s] the timetable loop's departure (on_timetable_)
  Point2 pose_;
  double heading_ = 0.0, speed_now_ = 0.0;
};

}  // namespace agent
}  // namespace gather
