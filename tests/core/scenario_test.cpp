#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gather_core/error.hpp"
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

}  // namespace
}  // namespace gather
