// world_params: defaults, a YAML with every field, and one clear line for a
// field out of range, of the wrong type, or unknown.
#include "gather_world/world_params.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace world {
namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& text) {
  try {
    load_world_params(write("world.yaml", text));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(WorldParams, DefaultsAndEveryField) {
  const WorldParams d = load_world_params("");
  EXPECT_EQ(d.max_speed, 0.0);  // auto: the team's
  EXPECT_EQ(d.laser_rays, 181);
  EXPECT_EQ(d.nav_period, 0.2);
  const WorldParams p = load_world_params(
      write("all.yaml",
            "robot: {max_speed: 0.6, max_turn_rate: 120, response_time: 0.1, radius: 0.25}\n"
            "laser: {range: 8, rays: 91, fov: 270}\n"
            "navigator: {period: 0.1, ref_distance: 3, paths: 61, max_leg: 2, clearance: 0.3, blocked_after: 5, "
            "give_up_after: 30}\n"));
  EXPECT_EQ(p.max_speed, 0.6);
  EXPECT_EQ(p.laser_fov, 270.0);
  EXPECT_EQ(p.paths, 61);
  EXPECT_EQ(p.give_up_after, 30.0);
}

TEST(WorldParams, ABadFieldIsOneLineNamingIt) {
  EXPECT_NE(error_of("laser: {rays: 3}\n").find("laser.rays = 3 must be in [8, 2048]"), std::string::npos);
  EXPECT_NE(error_of("navigator: {period: -1}\n").find("navigator.period = -1"), std::string::npos);
  EXPECT_NE(error_of("robot: {max_speed: fast}\n").find("robot.max_speed"), std::string::npos);
  EXPECT_NE(error_of("robot: {wheels: 4}\n").find("wheels"), std::string::npos);
  EXPECT_NE(error_of("lidar: {}\n").find("lidar"), std::string::npos);
  const std::string e = error_of("navigator: {paths: .nan}\n");
  EXPECT_NE(e.find("navigator.paths"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace world
}  // namespace gather
