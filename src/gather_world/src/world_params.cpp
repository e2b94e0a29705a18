#include "gather_world/world_params.hpp"

#include "gather_core/error.hpp"
#include "gather_core/yaml_fields.hpp"

namespace gather {
namespace world {

void check_params(const WorldParams& p, const std::string& where) {
  // 0 means auto for max_speed, radius and clearance.
  if (p.max_speed != 0) require_in_range(p.max_speed, 0, 10, where, "robot.max_speed", " m/s", true);
  require_in_range(p.max_turn_rate, 0, 720, where, "robot.max_turn_rate", " deg/s", true);
  require_in_range(p.response_time, 0, 5, where, "robot.response_time", " s");
  if (p.radius != 0) require_in_range(p.radius, 0, 5, where, "robot.radius", " m", true);
  require_in_range(p.laser_range, 0.5, 50, where, "laser.range", " m", true);
  require_in_range(p.laser_rays, 8, 2048, where, "laser.rays");
  require_in_range(p.laser_fov, 0, 360, where, "laser.fov", " deg", true);
  require_in_range(p.nav_period, 0.02, 1, where, "navigator.period", " s");
  require_in_range(p.ref_distance, 1, 20, where, "navigator.ref_distance", " m");
  require_in_range(p.paths, 11, 361, where, "navigator.paths");
  require_in_range(p.max_leg, 0.2, 20, where, "navigator.max_leg", " m", true);
  require_in_range(p.clearance, 0, 5, where, "navigator.clearance", " m");
  require_in_range(p.blocked_after, 1, 600, where, "navigator.blocked_after", " s");
  require_in_range(p.give_up_after, 1, 3600, where, "navigator.give_up_after", " s");
}

WorldParams load_world_params(const std::string& path) {
  WorldParams p;
  if (path.empty()) return p;
  const YAML::Node root = yaml::load_file(path);
  if (!root.IsMap()) throw Error(path, "expected a mapping with robot, laser and navigator sections");
  const yaml::Fields top(root, path, "");
  top.allow({"robot", "laser", "navigator"});
  const yaml::Fields robot = top.section("robot");
  robot.allow({"max_speed", "max_turn_rate", "response_time", "radius"});
  p.max_speed = robot.optional("max_speed", p.max_speed);
  p.max_turn_rate = robot.optional("max_turn_rate", p.max_turn_rate);
  p.response_time = robot.optional("response_time", p.response_time);
  p.radius = robot.optional("radius", p.radius);
  const yaml::Fields laser = top.section("laser");
  laser.allow({"range", "rays", "fov"});
  p.laser_range = laser.optional("range", p.laser_range);
  p.laser_rays = laser.optional("rays", p.laser_rays);
  p.laser_fov = laser.optional("fov", p.laser_fov);
  const yaml::Fields nav = top.section("navigator");
  nav.allow({"period", "ref_distance", "paths", "max_leg", "clearance", "blocked_after", "give_up_after"});
  p.nav_period = nav.optional("period", p.nav_period);
  p.ref_distance = nav.optional("ref_distance", p.ref_distance);
  p.paths = nav.optional("paths", p.paths);
  p.max_leg = nav.optional("max_leg", p.max_leg);
  p.clearance = nav.optional("clearance", p.clearance);
  p.blocked_after = nav.optional("blocked_after", p.blocked_after);
  p.give_up_after = nav.optional("give_up_after", p.give_up_after);
  check_params(p, path);
  return p;
}

}  // namespace world
}  // namespace gather
