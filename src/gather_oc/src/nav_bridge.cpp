#include "gather_oc/nav_bridge.hpp"

#include <cmath>

namespace gather {
namespace oc {

using agent::NavCommand;
using agent::NavState;

NavBridge::NavBridge(int agent, NavBridgeParams params) : params_(params) {
  status_.agent = static_cast<int16_t>(agent);
  pose_.agent = static_cast<int16_t>(agent);
}

bool NavBridge::take_changed() {
  const bool c = changed_;
  changed_ = false;
  return c;
}

void NavBridge::set_state(NavState s) {
  if (status_.state != s) status_.state = s, changed_ = true;
}

MoveBaseOrder NavBridge::goal_for(int k, double now) {
  // Arrive heading on to the next waypoint, or as it came to the last.
  const Point2 p = command_.points[k];
  Point2 from = k > 0 ? command_.points[k - 1] : pose_.at, to = p;
  if (k + 1 < command_.n) from = p, to = command_.points[k + 1];
  MoveBaseOrder o;
  o.kind = MoveBaseOrder::Kind::kGoal;
  o.at = p;
  o.yaw = (to.x == from.x && to.y == from.y) ? pose_.heading : std::atan2(to.y - from.y, to.x - from.x);
  goal_sent_at_ = now, goal_heard_ = false;
  goal_id_.clear();
  ++goals_sent_;
  return o;
}

MoveBaseOrder NavBridge::cancel_ours() {
  const bool out = goal_sent_at_ >= 0;
  goal_sent_at_ = -1.0;
  if (!out) return {};
  MoveBaseOrder o;
  o.kind = MoveBaseOrder::Kind::kCancel;
  o.goal_id = goal_id_;  // "" when move_base has not reported it: every goal
  return o;
}

MoveBaseOrder NavBridge::command(const NavCommand& c, double now) {
  if (have_command_ && c.id == command_.id) return {};  // a repeat
  command_ = c;
  have_command_ = true;
  status_.command = c.id;
  status_.reached = 0;
  status_.has_eta = false;
  changed_ = true;
  still_at_ = pose_.at, still_since_ = now;
  if (c.kind == NavCommand::Kind::kStop || c.n == 0) {
    status_.state = NavState::kIdle;
    cancelled_ = true;
    MoveBaseOrder o = cancel_ours();
    o.kind = MoveBaseOrder::Kind::kCancel;  // stop, whatever was out
    return o;
  }
  cancelled_ = false;
  current_ = 0;
  status_.state = NavState::kActive;
  // Waypoints it already stands on count at once.
  while (has_pose_ && current_ < c.n && distance(pose_.at, c.points[current_]) <= c.tolerance[current_])
    status_.reached_at[status_.reached++] = now, ++current_;
  if (current_ == c.n) {  // there already: the goal of the command before stops
    status_.state = NavState::kReached;
    return cancel_ours();
  }
  return goal_for(current_, now);
}

MoveBaseOrder NavBridge::reached(double now) {
  status_.reached_at[status_.reached++] = now;
  changed_ = true;
  ++current_;
  if (current_ >= command_.n) {  // within the last one's tolerance: stop there
    set_state(NavState::kReached);
    return cancel_ours();
  }
  return goal_for(current_, now);
}

MoveBaseOrder NavBridge::pose(Point2 at, double heading, double now) {
  if (has_pose_ && now > pose_.stamp) {
    const double dt = now - pose_.stamp;
    pose_.v = distance(at, pose_.at) / dt;
    pose_.w = std::remainder(heading - pose_.heading, 2.0 * M_PI) / dt;
  }
  pose_.at = at, pose_.heading = heading, pose_.stamp = now;
  if (!has_pose_) still_at_ = at, still_since_ = now;
  has_pose_ = true;
  if (!have_command_ || command_.kind != NavCommand::Kind::kGo) return {};
  if (status_.state != NavState::kActive && status_.state != NavState::kBlocked) return {};
  // Progress, or none for a while.
  if (distance(at, still_at_) >= params_.blocked_move_m) {
    still_at_ = at, still_since_ = now;
    set_state(NavState::kActive);
  } else if (now - still_since_ > params_.blocked_after_s) {
    set_state(NavState::kBlocked);
  }
  if (distance(at, command_.points[current_]) <= command_.tolerance[current_]) return reached(now);
  return {};
}

MoveBaseOrder NavBridge::goal_status(const std::vector<GoalReport>& goals, double now) {
  if (goal_sent_at_ < 0 || cancelled_) return {};
  const GoalReport* ours = nullptr;
  if (goal_id_.empty()) {  // the first goal move_base took after ours went out
    for (const GoalReport& g : goals)
      if (g.stamp + 1e-3 >= goal_sent_at_ && (!ours || g.stamp < ours->stamp)) ours = &g;
    if (!ours) return {};
    goal_id_ = ours->id, goal_stamp_ = ours->stamp;
  } else {
    for (const GoalReport& g : goals)
      if (g.id == goal_id_) ours = &g;
    if (!ours) return {};
  }
  goal_heard_ = true;
  for (const GoalReport& g : goals)  // someone else's goal, newer, under way: ours is over
    if (g.id != goal_id_ && g.stamp > goal_stamp_ &&
        (g.status == GoalStatus::kPending || g.status == GoalStatus::kActive)) {
      set_state(NavState::kFailed);
      goal_sent_at_ = -1.0;
      return {};
    }
  switch (ours->status) {
    case GoalStatus::kSucceeded: return reached(now);
    case GoalStatus::kAborted:
    case GoalStatus::kRejected:
    case GoalStatus::kPreempted:
    case GoalStatus::kRecalled:
    case GoalStatus::kLost:
      set_state(NavState::kFailed);  // reached: the waypoints before this one
      goal_sent_at_ = -1.0;
      return {};
    default: return {};
  }
}

MoveBaseOrder NavBridge::tick(double now) {
  if (goal_sent_at_ >= 0 && !goal_heard_ && now - goal_sent_at_ > params_.resend_after_s &&
      (status_.state == NavState::kActive || status_.state == NavState::kBlocked))
    return goal_for(current_, now);
  return {};
}

}  // namespace oc
}  // namespace gather
