#pragma once
// A robot behind the robot interface (docs/robots.md), as the agent's
// MotionBackend: commands go out as NavCommands through a NavCommandSink,
// poses and statuses come in (on_pose, on_status) from LCM
// (gather_agent --motion lcm) or from gather_world next to a team in one
// process. The agent never assumes its robot arrived: waypoints count as
// reached when the robot says so, at the time it says (converted from the
// robot's clock to mission time by the report's age). What the robot sends
// is checked: a pose that is not a number or off the map's free space, a
// localisation worse than the agent accepts, a status for another command
// or one that goes back on what it said are dropped and counted; a robot
// that falls silent is a fault (fault()), cleared when it speaks again.
#include <cstdint>
#include <string>
#include <vector>

#include "gather_agent/motion/robot_interface.hpp"

namespace gather {
namespace agent {

struct RobotBaseParams {
  // [s] of mission time without a pose or a status (or, after a command,
  // without a status for it) before the robot is silent. Range [0.2, 600].
  double silence_s = 2.0;
  // [m] a pose whose uncertainty (sigma) is worse is not taken: the robot
  // is lost. Range [0.01, 100].
  double max_sigma_m = 1.0;
  // [m] a waypoint counts as reached within this distance (sent with every
  // command). Range [0.01, 10].
  double tolerance_m = 0.25;
  // [s] a command under way is sent again this often (a robot that missed
  // it, or restarted, picks it up). Range [0.1, 60].
  double resend_s = 1.0;
};
// Throws gather::Error("robot base params", "<field> = <value> must be in
// <range>") for a field outside its range.
void check_params(const RobotBaseParams& params);

// What the agent dropped of what its robot sent, by reason.
struct RobotLinkCounters {
  int64_t poses = 0, statuses = 0;  // taken
  int64_t bad_pose = 0;             // not a number, or off the map's free space
  int64_t lost_pose = 0;            // sigma over max_sigma_m
  int64_t stale_status = 0;         // about another command than the current one
  int64_t bad_status = 0;           // reached past the command, going back, times after its stamp or not numbers
  int64_t commands = 0;             // commands sent (repeats included)
  int64_t faults = 0;               // times the robot became faulty (silent, off the map, lost)
};

class RobotBase : public MotionBackend {
 public:
  // `grid`: the map poses are checked against (it must outlive the base);
  // `start`: where the robot is before it reports; `speed` [m/s]: the team
  // speed, for its own estimates when the robot sends none; `sink` receives
  // every command (it must outlive the base). Throws gather::Error naming
  // the field when `params` are out of range.
  RobotBase(const OccupancyGrid& grid, int agent, Point2 start, double speed, NavCommandSink& sink,
            const RobotBaseParams& params = {});

  // What the robot reported, taken at mission time `now` [s] (the report is
  // as old as its stamp says it was when it arrived: none, on a local link).
  void on_pose(const RobotPose& pose, double now);
  void on_status(const NavStatus& status, double now);
  // The lockstep tick the commands sent from now on belong to (simulation;
  // -1: a real robot).
  void set_tick(int64_t tick) { tick_ = tick; }

  void go(const Waypoint* legs, std::size_t n, double now) override;
  void stop(double now) override;
  void update(double now) override;
  Point2 pose() const override { return pose_; }
  double heading() const override { return heading_; }
  double speed() const override { return v_; }
  NavState state() const override { return state_; }
  std::size_t legs_done() const override { return reached_; }
  double arrived_at(std::size_t leg) const override { return arrived_[leg]; }
  double arrival_estimate() const override;
  BaseFault fault() const override { return fault_; }
  std::size_t max_legs() const override { return kMaxNavWaypoints; }
  uint32_t path_revision() const override { return revision_; }
  std::size_t path(Point2* out, std::size_t max) const override;

  const RobotLinkCounters& counters() const { return counters_; }
  int32_t contacts() const { return contacts_; }  // robot-robot contacts the robot reported (simulation)
  // One line on the current fault ("" when none), and on the first one of
  // its life.
  const std::string& fault_text() const { return fault_text_; }
  const std::string& first_fault() const { return first_fault_; }

 private:
  void set_fault(BaseFault f, double now, const char* why);
  bool on_free_space(Point2 p) const;

  const OccupancyGrid& grid_;
  int agent_;
  double speed_;
  NavCommandSink& sink_;
  RobotBaseParams params_;
  NavCommand command_;  // the current command (kind kStop: none under way)
  double sent_at_ = 0.0;
  double last_sent_ = -1e300;
  std::vector<Waypoint> legs_;  // the current command as planned
  std::size_t n_ = 0;
  int64_t tick_ = -1;
  // What the robot said.
  Point2 pose_;
  double heading_ = 0.0, v_ = 0.0;
  double heard_at_ = 0.0;          // [s] its latest pose or status
  double status_heard_at_ = -1.0;  // [s] its latest status about the current command (-1: none yet)
  NavState state_ = NavState::kIdle;
  std::size_t reached_ = 0;
  std::vector<double> arrived_;  // [s] mission time, per waypoint reached
  double eta_ = kNoEstimate;     // [s] its estimate, in mission time
  int32_t contacts_ = 0;
  double now_ = 0.0;
  BaseFault fault_ = BaseFault::kNone;
  std::string fault_text_, first_fault_;
  uint32_t revision_ = 0;
  RobotLinkCounters counters_;
};

}  // namespace agent
}  // namespace gather
