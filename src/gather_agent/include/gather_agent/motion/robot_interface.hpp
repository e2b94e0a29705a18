#pragma once
// The robot interface's messages as the agent and gather_world see them:
// plain, fixed-size structs with bounded arrays. Their wire form is the LCM
// types robot_pose_t, nav_command_t, nav_status_t and, for views only,
// robot_scan_t (lcm/*.lcm; the
// contract for integrators is docs/robots.md); only transport/lcm_robot
// converts between the two. One set of channels per agent id.
#include <cstdint>
#include <string>

#include "gather_agent/motion/motion_backend.hpp"

namespace gather {
namespace agent {

constexpr int kMaxNavWaypoints = 256;  // waypoints in one navigation command
constexpr int kMaxScanRays = 2048;     // rays in one laser scan

// Channel names of agent `agent`'s robot.
std::string robot_pose_channel(int agent);     // GATHER_ROBOT_POSE_<agent>
std::string robot_command_channel(int agent);  // GATHER_ROBOT_CMD_<agent>
std::string robot_status_channel(int agent);   // GATHER_ROBOT_STATUS_<agent>
std::string robot_scan_channel(int agent);     // GATHER_ROBOT_SCAN_<agent> (optional, for views)

struct RobotPose {
  int16_t agent = 0;
  int64_t tick = -1;     // simulation: the lockstep tick it is for; a real robot: -1
  double stamp = 0.0;    // [s] robot clock
  Point2 at;             // [m] map frame
  double heading = 0.0;  // [rad]
  double v = 0.0;        // [m/s]
  double w = 0.0;        // [rad/s]
  double sigma = 0.0;    // [m] 1-sigma localisation uncertainty
};

struct NavCommand {
  enum class Kind : uint8_t { kGo = 1, kStop = 2 };
  int16_t agent = 0;
  int64_t tick = -1;
  int32_t id = 0;
  Kind kind = Kind::kStop;
  uint16_t n = 0;
  Point2 points[kMaxNavWaypoints];
  double after[kMaxNavWaypoints];      // [s] planned time of each, after the command was sent
  double tolerance[kMaxNavWaypoints];  // [m] how close counts as reached
};

struct NavStatus {
  int16_t agent = 0;
  int64_t tick = -1;
  double stamp = 0.0;  // [s] robot clock
  int32_t command = 0;
  NavState state = NavState::kIdle;
  uint16_t reached = 0;
  double reached_at[kMaxNavWaypoints];  // [s] robot clock
  bool has_eta = false;
  double eta = 0.0;      // [s] robot clock
  int32_t contacts = 0;  // simulation: robot-robot contacts so far
};

// A laser scan, for views (the agent never reads one): ray k at
// angle_min + k * angle_increment from the heading, as sensor_msgs/LaserScan.
struct RobotScan {
  int16_t agent = 0;
  int64_t tick = -1;
  double stamp = 0.0;                              // [s] robot clock
  Point2 at;                                       // [m] the laser's position in the map frame
  double heading = 0.0;                            // [rad]
  float angle_min = 0.0f, angle_increment = 0.0f;  // [rad]
  float range_max = 0.0f;                          // [m] no return: +inf
  uint16_t rays = 0;
  float ranges[kMaxScanRays];  // [m]
};

// Where an agent's navigation commands go (the robot's side of the link:
// LCM, or gather_world next to a team in one process).
class NavCommandSink {
 public:
  virtual ~NavCommandSink() = default;
  virtual void send(const NavCommand& command) = 0;
};

}  // namespace agent
}  // namespace gather
