#pragma once
// Scripted robots behind the robot interface, for the runtime's tests: each
// drives straight from waypoint to waypoint (through walls: the map is not
// their business here) at a speed, and can be scripted to be slow, to fail
// a waypoint, to fall silent, or to report a pose that is not a number or
// off the map. A RobotWorld (runner/robot_world.hpp) for TeamRunner, and a
// robot to drive one RobotBase by hand.
#include <cmath>
#include <limits>
#include <vector>

#include "gather_agent/runner/robot_world.hpp"

namespace gather {
namespace agent {
namespace agent_testing {

struct RobotScript {
  double speed = 1.0;  // [m/s]
  // Waypoints (counted over the robot's life, from 0) it fails: it stops
  // short of the i-th waypoint it is sent towards and reports FAILED.
  int fail_waypoint = -1;
  double silent_from = std::numeric_limits<double>::infinity();   // [s] no pose or status from then on
  double nan_from = std::numeric_limits<double>::infinity();      // [s] its pose is NaN from then on
  double off_map_from = std::numeric_limits<double>::infinity();  // [s] its pose is far off the map from then on
  bool eta = true;                                                // it reports an arrival estimate
};

class ScriptedRobot {
 public:
  ScriptedRobot(int agent, Point2 start, RobotScript script) : agent_(agent), at_(start), script_(script) {}

  void command(const NavCommand& c) {
    if (c.id == command_.id) return;  // a repeat
    command_ = c;
    reached_ = 0;
    state_ = c.kind == NavCommand::Kind::kGo ? NavState::kActive : NavState::kIdle;
  }
  void step(double t) {
    const double dt = t - t_;
    t_ = t;
    v_ = 0.0;
    if (state_ != NavState::kActive) return;
    double left = script_.speed * dt;
    while (left > 0 && reached_ < command_.n) {
      if (waypoints_seen_ == script_.fail_waypoint) {
        state_ = NavState::kFailed;
        ++waypoints_seen_;  // once: the next command's waypoints are reached
        return;
      }
      const Point2 goal = command_.points[reached_];
      const double d = std::hypot(goal.x - at_.x, goal.y - at_.y);
      if (d <= left) {
        at_ = goal, left -= d;
        reached_at_[reached_] = t - left / script_.speed;
        ++reached_, ++waypoints_seen_;
      } else {
        heading_ = std::atan2(goal.y - at_.y, goal.x - at_.x);
        at_ = Point2{at_.x + left / d * (goal.x - at_.x), at_.y + left / d * (goal.y - at_.y)};
        left = 0;
      }
    }
    v_ = script_.speed;
    if (reached_ == command_.n) state_ = NavState::kReached;
  }
  // Moved by hand (it stepped aside for another robot, or was pushed).
  void place(Point2 p) { at_ = p; }
  bool talks(double t) const { return t < script_.silent_from; }
  RobotPose pose(int64_t tick) const {
    RobotPose p;
    p.agent = static_cast<int16_t>(agent_), p.tick = tick, p.stamp = t_;
    p.at = at_, p.heading = heading_, p.v = v_;
    if (t_ >= script_.nan_from) p.at.x = std::numeric_limits<double>::quiet_NaN();
    if (t_ >= script_.off_map_from) p.at = Point2{-1000.0, -1000.0};
    return p;
  }
  NavStatus status(int64_t tick) const {
    NavStatus s;
    s.agent = static_cast<int16_t>(agent_), s.tick = tick, s.stamp = t_;
    s.command = command_.id, s.state = state_;
    s.reached = static_cast<uint16_t>(reached_);
    for (int i = 0; i < reached_; ++i) s.reached_at[i] = reached_at_[i];
    if (script_.eta && state_ == NavState::kActive) {
      double left = 0.0;
      Point2 from = at_;
      for (int i = reached_; i < command_.n; ++i) {
        left += std::hypot(command_.points[i].x - from.x, command_.points[i].y - from.y);
        from = command_.points[i];
      }
      s.has_eta = true, s.eta = t_ + left / script_.speed;
    }
    return s;
  }
  Point2 at() const { return at_; }

 private:
  int agent_;
  Point2 at_;
  RobotScript script_;
  NavCommand command_;
  NavState state_ = NavState::kIdle;
  int reached_ = 0, waypoints_seen_ = 0;
  double reached_at_[kMaxNavWaypoints] = {};
  double t_ = 0.0, heading_ = 0.0, v_ = 0.0;
};

// A team of scripted robots.
class ScriptedWorld : public RobotWorld {
 public:
  ScriptedWorld(const std::vector<Point2>& starts, const std::vector<RobotScript>& scripts) {
    for (std::size_t i = 0; i < starts.size(); ++i) robots_.emplace_back(static_cast<int>(i), starts[i], scripts[i]);
  }
  void step(int64_t tick, double t, const std::vector<NavCommand>& commands, std::vector<RobotPose>& poses,
            std::vector<NavStatus>& statuses) override {
    for (const NavCommand& c : commands) robots_[static_cast<std::size_t>(c.agent)].command(c);
    poses.clear(), statuses.clear();
    for (ScriptedRobot& r : robots_) {
      r.step(t);
      if (!r.talks(t)) continue;
      poses.push_back(r.pose(tick));
      statuses.push_back(r.status(tick));
    }
  }
  ScriptedRobot& robot(int agent) { return robots_[static_cast<std::size_t>(agent)]; }

 private:
  std::vector<ScriptedRobot> robots_;
};

}  // namespace agent_testing
}  // namespace agent
}  // namespace gather
