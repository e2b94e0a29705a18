// motion/simulated_base: a worker's ideal base drives each leg on a free path
// at the pace that reaches its end at the planned time, and reports it.
#include "gather_agent/motion/simulated_base.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../core/predicate_grid.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

using testing_support::predicate_grid;

Mask free_cells(const OccupancyGrid& grid) {
  Mask m(grid.frame(), 0);
  for (std::size_t i = 0; i < grid.size(); ++i) m[i] = grid.free_mask()[i];
  return m;
}

TEST(SimulatedBase, ALegInTheOpenIsAStraightLineDrivenAtThePlannedPace) {
  const OccupancyGrid grid = predicate_grid(
      40, 20, [](int, int) { return true; }, 0.1);
  const Mask traversable = free_cells(grid);
  GridAStar paths(grid, traversable);
  SimulatedBase base(grid, paths, Point2{0.55, 0.55}, 4, 1.0);
  const Waypoint leg{Point2{3.55, 0.55}, 13.0};  // 3 m in 3 s from t = 10
  base.go(&leg, 1, 10.0);
  EXPECT_EQ(base.path_points(0), 2u);
  base.update(11.5);
  EXPECT_NEAR(base.pose().x, 2.05, 1e-6);
  EXPECT_NEAR(base.pose().y, 0.55, 1e-6);
  EXPECT_EQ(base.legs_done(), 0u);
  EXPECT_EQ(base.state(), NavState::kActive);
  EXPECT_NEAR(base.speed(), 1.0, 1e-9);
  base.update(13.0);
  EXPECT_EQ(base.legs_done(), 1u);
  EXPECT_DOUBLE_EQ(base.arrived_at(0), 13.0);
  EXPECT_NEAR(base.pose().x, 3.55, 1e-6);
  EXPECT_EQ(base.state(), NavState::kReached);
  EXPECT_DOUBLE_EQ(base.arrival_estimate(), 13.0);
  EXPECT_NEAR(base.heading(), 0.0, 1e-12);  // east
  base.stop(13.0);
  EXPECT_EQ(base.state(), NavState::kIdle);
  base.update(20.0);
  EXPECT_NEAR(base.pose().x, 3.55, 1e-6);  // stopped: it stays
}

TEST(SimulatedBase, AWallSendsTheLegThroughItsDoorOnFreeCells) {
  // A wall at column 20 with a door in rows 15-17 (0.1 m cells).
  const OccupancyGrid grid = predicate_grid(
      40, 20, [](int r, int c) { return c != 20 || (r >= 15 && r <= 17); }, 0.1);
  const Mask traversable = free_cells(grid);
  GridAStar paths(grid, traversable);
  SimulatedBase base(grid, paths, Point2{0.55, 0.25}, 4, 1.0);
  const Waypoint leg{Point2{3.55, 0.25}, 100.0};
  base.go(&leg, 1, 0.0);
  ASSERT_GT(base.path_points(0), 2u);  // not the straight line through the wall
  bool through_door = false;
  for (std::size_t i = 0; i < base.path_points(0); ++i) {
    const Point2 p = base.path_point(0, i);
    const Cell c = grid.world_to_cell(p);
    ASSERT_TRUE(grid.contains(c));
    EXPECT_TRUE(grid.free_mask()[grid.index(c)]) << p.x << ", " << p.y;
    through_door = through_door || (c.col == 20 && c.row >= 15 && c.row <= 17);
  }
  // Straightened corners may step over the door column between two points:
  // the path must at least reach the door's height.
  double highest = 0.0;
  for (std::size_t i = 0; i < base.path_points(0); ++i) highest = std::max(highest, base.path_point(0, i).y);
  EXPECT_TRUE(through_door || highest >= 1.5);
  base.update(100.0);
  EXPECT_NEAR(base.pose().x, 3.55, 1e-6);
  EXPECT_NEAR(base.pose().y, 0.25, 1e-6);
}

TEST(SimulatedBase, ItsDetourFactorHasARange) {
  const OccupancyGrid grid = predicate_grid(
      10, 10, [](int, int) { return true; }, 0.1);
  const Mask traversable = free_cells(grid);
  GridAStar paths(grid, traversable);
  SimulatedBaseParams params;
  params.detour = 0.5;
  try {
    SimulatedBase bad(grid, paths, Point2{0.05, 0.05}, 2, 1.0, nullptr, nullptr, params);
    FAIL() << "detour 0.5 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("detour = 0.5 must be in [1, 10]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace agent
}  // namespace gather
