#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_loader.hpp"
#include "gather_core/grid/map_saver.hpp"
#include "gather_core/input_ranges.hpp"
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

// Every range of the one table (input_ranges.hpp): declared once per input,
// ends in order, its check accepting exactly what it says (tests/cli/
// range_ends.py tries each one through the command that reads it).
TEST(InputRanges, EachIsDeclaredOnceAndItsCheckAcceptsItsEndsAndNothingOutside) {
  std::set<std::pair<std::string, std::string>> seen;
  ASSERT_EQ(input_ranges().size(), static_cast<std::size_t>(range::kCount));
  for (const InputRange& r : input_ranges()) {
    SCOPED_TRACE(std::string(r.input) + " " + r.key);
    EXPECT_TRUE(seen.insert({r.input, r.key}).second) << "declared twice";
    EXPECT_LT(r.lo, r.hi);
    EXPECT_EQ(r.accepts(r.lo), (r.flags & kRangeOpenLo) == 0);
    EXPECT_EQ(r.accepts(r.hi), (r.flags & kRangeOpenHi) == 0);
    EXPECT_TRUE(r.accepts((r.lo + r.hi) / 2) || r.integer());
    EXPECT_FALSE(r.accepts(r.hi + std::max(1.0, std::abs(r.hi) * 1e-6)));
    const double below = r.lo - std::max(1.0, std::abs(r.lo) * 1e-6);
    EXPECT_EQ(r.accepts(below), (r.flags & kRangeZero) != 0 && below == 0.0);
    EXPECT_FALSE(r.accepts(std::nan("")));
    EXPECT_FALSE(r.accepts(INFINITY));
    if (r.integer() && r.lo + 0.5 < r.hi) {
      EXPECT_FALSE(r.accepts(r.lo + 0.5));
    }
  }
  EXPECT_EQ(input_range(range::kPeriod).hi, kMaxPeriod);
  EXPECT_EQ(input_range(range::kCyclePeriod).hi, kMaxPeriod);
}

TEST(InputRanges, AValueOutsideIsOneLineNamingTheFileTheKeyAndTheRange) {
  auto message = [](range::Id id, double v) {
    try {
      check_range(id, v, "s.yaml");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(range::kTeamSpeed, 0.001), "s.yaml: team.speed = 0.001 must be in [0.01, 100] m/s");
  EXPECT_EQ(message(range::kTeamAgents, 2.5), "s.yaml: team.agents = 2.5 must be in [1, 300] (an integer)");
  EXPECT_EQ(message(range::kPeriod, 0), "accepted");  // automatic
  EXPECT_EQ(message(range::kPeriod, 0.5), "s.yaml: mission.period = 0.5 must be in 0 or [1, 100000] s");
  EXPECT_EQ(message(range::kCyclePeriod, 0), "s.yaml: cycle_period_s = 0 must be in (0, 100000] s");
}

}  // namespace
}  // namespace gather
