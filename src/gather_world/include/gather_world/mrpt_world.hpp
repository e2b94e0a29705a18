#pragma once
// The robot world: every robot of a team as an MRPT differential-drive
// vehicle (mrpt::kinematics::CVehicleSimul_DiffDriven) following the
// waypoints its agent sends with MRPT's reactive navigator
// (CReactiveNavigationSystem over TP-space PTGs, through a
// CRobot2NavInterface on the world's clock) and a 2-D laser simulated on
// the map, in which the other robots appear as obstacles. Each robot plans
// its own way between two waypoints (A* on the map kept off the walls) and
// hands the navigator targets along it, as a robot with a global and a
// local planner does. The robots keep to simple traffic rules a real fleet
// has: two meeting head on keep right, or one makes way (the higher id);
// an idle robot in a moving one's way steps aside (within a metre of where
// it stopped); one that makes no progress says BLOCKED after
// blocked_after, backs off and tries another way, and gives the waypoint
// up (FAILED) after give_up_after. It speaks only the robot interface
// (agent::RobotWorld: commands in; poses and statuses out), so to its agent
// each robot is what a real robot would be.
//
// Deterministic: the navigators run on a simulated MRPT clock that the
// world advances (mrpt::Clock in Simulated mode: one world per process),
// robots are stepped in id order, nothing random. Same commands at the same
// ticks, same poses, bit for bit. The only code that sees MRPT (pimpl).
#include <memory>
#include <vector>

#include "gather_agent/motion/robot_interface.hpp"
#include "gather_agent/runner/robot_world.hpp"
#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_world/world_params.hpp"

namespace gather {
namespace world {

// What a world did, per robot.
struct RobotTally {
  int64_t contacts = 0;   // times it touched another robot (drove into it, or came within a hair of it)
  int64_t blocked = 0;    // times it reported BLOCKED
  int64_t failed = 0;     // waypoints it gave up
  int64_t replans = 0;    // global paths planned (commands, and again after a block)
  double driven_m = 0.0;  // [m]
};

class MrptWorld : public agent::RobotWorld {
 public:
  // `map`: the map the robots drive on (full resolution); `starts`: where
  // robot k (agent k) starts [m], heading along the map's x axis;
  // `team_speed` [m/s] and `team_radius` [m]: the scenario's, for the
  // params' automatic values. Throws gather::Error naming the field for
  // params out of range, and what MRPT says of its navigator's
  // configuration (a bug of ours, reported as one line).
  MrptWorld(const OccupancyGrid& map, const std::vector<Point2>& starts, double team_speed, double team_radius,
            const WorldParams& params);
  ~MrptWorld() override;
  MrptWorld(const MrptWorld&) = delete;
  MrptWorld& operator=(const MrptWorld&) = delete;

  void step(int64_t tick, double t, const std::vector<agent::NavCommand>& commands,
            std::vector<agent::RobotPose>& poses, std::vector<agent::NavStatus>& statuses) override;

  int robots() const;
  const RobotTally& tally(int robot) const;
  // Robot `robot`'s laser scan, at most a navigation period old (for
  // views: gather_world --scans; taking one changes nothing the robots do).
  // Ranges are what each ray met (+inf: nothing within laser_range), the
  // other robots included.
  void scan(int robot, agent::RobotScan& out);
  double radius() const;     // [m] as used (auto resolved)
  double max_speed() const;  // [m/s] as used
  // Wall time spent [ms]: navigators (laser included), vehicles, the rest.
  double nav_ms() const;
  double vehicle_ms() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace world
}  // namespace gather
