#pragma once
// The robot interface on top of move_base (docs/robots.md, "A robot that
// runs ROS"): what robot_bridge decides, without ROS. The agent's command
// (waypoints with tolerances) goes to move_base one waypoint at a time as a
// goal (move_base_simple/goal); a waypoint counts as reached when the pose
// (from TF) is within its tolerance, or when move_base says its goal
// succeeded; move_base aborting (or dropping) the goal of a waypoint is the
// command FAILED at that waypoint; no progress for a while is BLOCKED.
// Times are the robot's clock [s] (ROS time).
#include <cstdint>
#include <string>
#include <vector>

#include "gather_agent/motion/robot_interface.hpp"
#include "gather_core/grid/raster.hpp"

namespace gather {
namespace oc {

struct NavBridgeParams {
  double blocked_after_s = 5.0;  // ACTIVE without moving blocked_move_m this long: BLOCKED
  double blocked_move_m = 0.05;
  double resend_after_s = 2.0;  // a goal move_base has not reported yet goes out again
};

// actionlib_msgs/GoalStatus::status.
enum class GoalStatus : uint8_t {
  kPending = 0,
  kActive = 1,
  kPreempted = 2,
  kSucceeded = 3,
  kAborted = 4,
  kRejected = 5,
  kPreempting = 6,
  kRecalling = 7,
  kRecalled = 8,
  kLost = 9,
};

// One goal of move_base/status.
struct GoalReport {
  std::string id;
  double stamp = 0.0;  // [s] its goal id's stamp (when move_base took it)
  GoalStatus status = GoalStatus::kPending;
};

// What to do with move_base.
struct MoveBaseOrder {
  enum class Kind : uint8_t { kNone, kGoal, kCancel } kind = Kind::kNone;
  Point2 at;            // kGoal: [m] map frame
  double yaw = 0.0;     // kGoal: [rad] the heading to arrive with
  std::string goal_id;  // kCancel: the goal to cancel ("": every goal)
};

class NavBridge {
 public:
  NavBridge(int agent, NavBridgeParams params = {});

  // A command from the agent (a repeat of the one under way changes nothing).
  MoveBaseOrder command(const agent::NavCommand& c, double now);
  // The robot's pose (from TF).
  MoveBaseOrder pose(Point2 at, double heading, double now);
  // move_base's status (every goal it reports). The bridge's goal is the
  // first one stamped at or after it went out (its id is kept from then);
  // a newer goal of another id that is under way took move_base over
  // (someone else's goal): FAILED.
  MoveBaseOrder goal_status(const std::vector<GoalReport>& goals, double now);
  // Called every cycle: a goal move_base has not taken goes out again.
  MoveBaseOrder tick(double now);

  // The status the agent gets (state, waypoints reached and when).
  const agent::NavStatus& status() const { return status_; }
  // The pose the agent gets (speeds from the last two poses).
  const agent::RobotPose& robot_pose() const { return pose_; }
  bool has_pose() const { return has_pose_; }
  // True once after every change of the status (publish it at once).
  bool take_changed();
  double goal_sent_at() const { return goal_sent_at_; }
  int64_t goals_sent() const { return goals_sent_; }
  int waypoints() const { return have_command_ ? command_.n : 0; }

 private:
  MoveBaseOrder goal_for(int k, double now);
  MoveBaseOrder reached(double now);  // the current waypoint counts as reached
  MoveBaseOrder cancel_ours();        // a cancel of the goal out, if any
  void set_state(agent::NavState s);

  NavBridgeParams params_;
  agent::NavCommand command_{};
  bool have_command_ = false;
  int current_ = 0;             // waypoint under way
  double goal_sent_at_ = -1.0;  // when its goal went out (-1: none out)
  bool goal_heard_ = false;     // move_base reported that goal
  std::string goal_id_;         // its id in move_base/status, once heard
  double goal_stamp_ = 0.0;     // and its stamp
  bool cancelled_ = false;
  agent::NavStatus status_{};
  agent::RobotPose pose_{};
  bool has_pose_ = false;
  bool changed_ = true;
  Point2 still_at_;  // where the robot was when it last moved blocked_move_m
  double still_since_ = 0.0;
  int64_t goals_sent_ = 0;
};

}  // namespace oc
}  // namespace gather
