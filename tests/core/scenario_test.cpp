#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_loader.hpp"
#include "gather_core/grid/map_saver.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_core/scenario/start_poses.hpp"

namespace gather {
namespace {

const std::string kIpa = std::string(GATHER_REPO_DIR) + "/../shared/maps/ipa/";

TEST(Scenario, LoadsIpaOfficeA) {
  const Scenario s = load_scenario(kIpa + "office_a.scenario.yaml");
  EXPECT_EQ(s.grid.width(), 1194);
  EXPECT_EQ(s.grid.height(), 685);
  EXPECT_DOUBLE_EQ(s.grid.resolution(), 0.05);
  EXPECT_EQ(s.team.agents, 20);
  EXPECT_EQ(s.planner.collectors_max, 8);
  EXPECT_TRUE(s.grid.is_free(s.grid.world_to_cell(s.oc)));
}

TEST(StartPoses, SpacedFreeAndNearTheOc) {
  const Scenario s = load_scenario(kIpa + "office_a.scenario.yaml");
  const auto poses = start_poses(s.grid, s.oc, 20, 0.6);
  ASSERT_EQ(poses.size(), 20u);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_TRUE(s.grid.is_free(s.grid.world_to_cell(poses[i])));
    EXPECT_GE(std::hypot(poses[i].x - s.oc.x, poses[i].y - s.oc.y), 0.6);
    EXPECT_LT(std::hypot(poses[i].x - s.oc.x, poses[i].y - s.oc.y), 6.0);
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_GE(std::hypot(poses[i].x - poses[j].x, poses[i].y - poses[j].y), 0.6 - 1e-9);
  }
}

TEST(MapSaver, ASavedMapLoadsBackCellForCell) {
  // Free (0), occupied (>= 65) and unknown (-1, and 1..64 of a scale map).
  std::vector<int8_t> values = {0, 100, -1, 0, 65, 64, 1, 0, 0, 99, -1, 0};
  std::vector<uint8_t> free(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) free[i] = values[i] == 0;
  const OccupancyGrid g(4, 3, 0.1f, Point2{-1.25, 2.5}, values, free);
  const std::string base = ::testing::TempDir() + "/gather_map_saver_" + std::to_string(::getpid()) + "/map";
  const std::string yaml = save_map(g, base);
  const OccupancyGrid back = load_map(yaml);
  ASSERT_EQ(back.width(), 4);
  ASSERT_EQ(back.height(), 3);
  EXPECT_DOUBLE_EQ(back.resolution(), g.resolution());
  EXPECT_DOUBLE_EQ(back.origin().x, -1.25);
  EXPECT_DOUBLE_EQ(back.origin().y, 2.5);
  const std::vector<int8_t> want = {0, 100, -1, 0, 100, -1, -1, 0, 0, 100, -1, 0};
  EXPECT_EQ(back.values(), want);
  EXPECT_EQ(back.free_mask(), free);
}

TEST(Scenario, SettingsWithoutAMapAndTheMapAttachedLater) {
  const std::string dir = ::testing::TempDir() + "/gather_scenario_nomap_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir + "/s.yaml");
    f << "oc: [1.0, 1.0]\nteam: {agents: 3}\n";
  }
  EXPECT_THROW(load_scenario(dir + "/s.yaml"), Error);  // the map is required here
  EXPECT_THROW(load_scenario_settings(dir + "/s.yaml", true), Error);
  Scenario s = load_scenario_settings(dir + "/s.yaml", false);
  EXPECT_TRUE(s.map_path.empty());
  EXPECT_EQ(s.team.agents, 3);
  EXPECT_EQ(s.grid.size(), 0u);
  std::vector<int8_t> v(400, 0);
  std::vector<uint8_t> free(400, 1);
  v[11 * 20 + 11] = 100, free[11 * 20 + 11] = 0;  // cell (11, 11) holds [1.1, 1.2) m
  attach_map(s, OccupancyGrid(20, 20, 0.1, Point2{0, 0}, v, free));
  EXPECT_EQ(s.grid.width(), 20);
  Scenario blocked = load_scenario_settings(dir + "/s.yaml", false);
  blocked.oc = Point2{1.15, 1.15};
  try {
    attach_map(blocked, OccupancyGrid(20, 20, 0.1, Point2{0, 0}, v, free));
    FAIL() << "an OC on an obstacle must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml"), std::string::npos) << e.what();
  }
  // The scenario rewritten to name a saved map loads whole.
  const std::string map_yaml = save_map(s.grid, dir + "/saved");
  write_scenario_with_map(dir + "/s.yaml", map_yaml, dir + "/with_map.yaml");
  const Scenario whole = load_scenario(dir + "/with_map.yaml");
  EXPECT_EQ(whole.grid.values(), s.grid.values());
  EXPECT_EQ(whole.team.agents, 3);
}

}  // namespace
}  // namespace gather
