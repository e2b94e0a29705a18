#pragma once
// gather_world's settings: the robots' kinematics, their laser and their
// navigator, from one YAML file (docs/robots.md, "gather_world"). Every
// field is optional and has a default; a field out of its range, of the
// wrong type or unknown is an error naming the file and the field.
#include <string>

namespace gather {
namespace world {

struct WorldParams {
  // robot: a differential-drive base (mrpt::kinematics::CVehicleSimul_DiffDriven).
  double max_speed = 0.0;       // [m/s] top speed; 0 (auto): 1.15 x the scenario's team.speed. (0, 10]
  double max_turn_rate = 90.0;  // [deg/s] (0, 720]
  double response_time = 0.2;   // [s] first-order lag of the wheels' speed behind a command. [0, 5]
  double radius = 0.0;          // [m] footprint (a disc); 0 (auto): the scenario's team.radius. (0, 5]
  // laser: a 2-D scan simulated on the map, other robots seen as discs.
  double laser_range = 5.0;  // [m] (0.5, 50]
  int laser_rays = 181;      // [8, 2048]
  double laser_fov = 360.0;  // [deg] (0, 360]
  // navigator: MRPT's reactive navigator (CReactiveNavigationSystem, TP-space
  // PTGs) following a path the robot's own global planner (A* on the map,
  // kept `clearance` off the walls) splits into targets `max_leg` apart.
  double nav_period = 0.2;      // [s] between two navigation steps of a robot. [0.02, 1]
  double ref_distance = 4.0;    // [m] how far its trajectories reach. [1, 20]
  int paths = 121;              // trajectories per PTG family. [11, 361]
  double max_leg = 3.0;         // [m] (0.2, 20]
  double clearance = 0.0;       // [m] off the walls; 0 (auto): radius + 0.05. [0, 5]
  double blocked_after = 10.0;  // [s] without progress: it reports BLOCKED, backs off and plans again. [1, 600]
  double give_up_after = 60.0;  // [s] without progress: it reports its waypoint FAILED. [1, 3600]
};

// Reads `path` ("" gives the defaults). Throws gather::Error(path, "<field>
// ...") naming the field.
WorldParams load_world_params(const std::string& path);
// Throws gather::Error(where, "<field> = <value> must be in <range>").
void check_params(const WorldParams& params, const std::string& where);

}  // namespace world
}  // namespace gather
