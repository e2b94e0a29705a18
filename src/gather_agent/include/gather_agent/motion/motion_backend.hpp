#pragma once
// The robot's base as a role sees it: the agent's side of the robot
// interface (docs/robots.md). A role sends its base navigation commands (a
// path of waypoints, each with the mission time the role plans to be there,
// or a stop) and reads back what the base reports: its pose (position,
// heading, speed), the state of the current command (active, reached,
// failed, blocked), the waypoints reached and when, an estimate of when it
// reaches the last one, and faults of the base itself (silent, off the map,
// lost). Planned times are hints; reported times are facts: a role never
// assumes its robot arrived, it reads state() and legs_done().
// Implementations:
// - SimulatedBase (motion/simulated_base.hpp): an ideal worker base that
//   reaches every waypoint at its planned time (the analytic simulator's
//   kinematics, for the equivalence checks);
// - RouteBase (motion/route_base.hpp): an ideal collector base, where its
//   timetable says when it drives a loop of its route on time;
// - RobotBase (motion/robot_base.hpp): a robot behind the robot interface's
//   messages: a real robot or gather_world's over LCM (gather_agent
//   --motion lcm), or gather_world's in one process;
// - Station: the OC, which never moves.
// Units: positions [m] in the map frame, headings [rad] counter-clockwise
// from the map's x axis, times [s] of mission time.
#include <cstddef>
#include <cstdint>
#include <limits>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace agent {

// The end of one leg: a point [m], when the role plans to be there [s],
// and how close counts as there [m] (0: the base's default; an ideal base
// reaches every waypoint exactly).
struct Waypoint {
  Point2 point;
  double arrive = 0.0;
  double tolerance = 0.0;
};

// The state of the current command, as the base reports it.
enum class NavState : uint8_t {
  kIdle = 0,     // no command (or stopped)
  kActive = 1,   // driving
  kReached = 2,  // every waypoint reached
  kFailed = 3,   // it gave up: the next waypoint cannot be reached (legs_done() were)
  kBlocked = 4,  // stuck for now (an obstacle, a robot in the way); it keeps trying
};
const char* nav_state_name(NavState s);

// What is wrong with the base itself (not with one command). A fault the
// role cannot work around ends its motion: it is reported once on stderr
// and in the agent's results, and the role carries on with what it holds.
enum class BaseFault : uint8_t {
  kNone = 0,
  kSilent = 1,  // no report from the robot for longer than its timeout
  kOffMap = 2,  // it reports a pose off the map's free space, or not a number
  kLost = 3,    // its localisation is worse than the agent accepts
};
const char* base_fault_name(BaseFault f);

class MotionBackend {
 public:
  static constexpr double kNoEstimate = std::numeric_limits<double>::infinity();

  virtual ~MotionBackend() = default;
  // A new command at mission time `now` [s]: drive through legs[0..n) in
  // order (1 <= n <= max_legs()), replacing the current one. From here on
  // state(), legs_done() and arrived_at() are about this command.
  virtual void go(const Waypoint* legs, std::size_t n, double now) = 0;
  // Stops where it is (the current command ends; state() is kIdle).
  virtual void stop(double now) = 0;
  // Takes in what the base reported up to mission time `now` [s]
  // (monotonic); a simulated base moves there.
  virtual void update(double now) = 0;

  virtual Point2 pose() const = 0;     // [m] position at the last update()
  virtual double heading() const = 0;  // [rad]
  virtual double speed() const = 0;    // [m/s] forward speed
  virtual NavState state() const = 0;
  virtual std::size_t legs_done() const = 0;             // waypoints of the current command reached
  virtual double arrived_at(std::size_t leg) const = 0;  // [s] when waypoint `leg` < legs_done() was reached
  // [s] when the base expects to reach the current command's last waypoint
  // (its arrival time once reached); kNoEstimate when it has none.
  virtual double arrival_estimate() const = 0;
  virtual BaseFault fault() const { return BaseFault::kNone; }
  virtual std::size_t max_legs() const = 0;

  // For views (RViz): the polyline the base plans to drive, and a number
  // that changes whenever that plan changes (go, stop). Writes at most `max`
  // points to `out` (of a longer path, its first `max`) and returns how
  // many; 0: no path to show.
  virtual uint32_t path_revision() const { return 0; }
  virtual std::size_t path(Point2* out, std::size_t max) const {
    (void)out, (void)max;
    return 0;
  }
};

// A base that never moves (the OC's station).
class Station : public MotionBackend {
 public:
  explicit Station(Point2 at) : pose_(at) {}
  void go(const Waypoint*, std::size_t, double) override {}
  void stop(double) override {}
  void update(double) override {}
  Point2 pose() const override { return pose_; }
  double heading() const override { return 0.0; }
  double speed() const override { return 0.0; }
  NavState state() const override { return NavState::kIdle; }
  std::size_t legs_done() const override { return 0; }
  double arrived_at(std::size_t) const override { return 0.0; }
  double arrival_estimate() const override { return kNoEstimate; }
  std::size_t max_legs() const override { return 0; }

 private:
  Point2 pose_;
};

}  // namespace agent
}  // namespace gather
