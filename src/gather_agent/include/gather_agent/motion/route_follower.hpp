#pragma once
// Simulated kinematics of a collector: it is where its timetable says
// (mission::RouteTimetable: the plan's route, loops synchronised with the
// OC's requests by plan::LoopSchedule), at every instant.
#include "gather_agent/motion/motion_backend.hpp"
#include "gather_core/mission/route_timetable.hpp"

namespace gather {
namespace agent {

class RouteFollower : public MotionBackend {
 public:
  explicit RouteFollower(Point2 start) : pose_(start) {}
  void go(const Waypoint*, std::size_t, double) override;  // throws: a collector drives its route
  void hold() override { route_ = nullptr; }
  void follow(const mission::RouteTimetable& timetable) override { route_ = &timetable; }
  void advance(double now) override {
    if (route_) pose_ = route_->position(now);
  }
  Point2 pose() const override { return pose_; }
  std::size_t legs_done() const override { return 0; }
  double arrived_at(std::size_t) const override { return 0.0; }
  std::size_t max_legs() const override { return 0; }

 private:
  const mission::RouteTimetable* route_ = nullptr;
  Point2 pose_;
};

}  // namespace agent
}  // namespace gather
