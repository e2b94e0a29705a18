#include <gtest/gtest.h>

#include "gather_core/grid/occupancy_grid.hpp"
#include "gather_core/grid/reachability.hpp"

namespace gather {
namespace {

OccupancyGrid make_grid(const std::vector<std::string>& rows_top_first, double res = 0.5, Point2 origin = {1.0, -2.0}) {
  const int h = static_cast<int>(rows_top_first.size());
  const int w = static_cast<int>(rows_top_first[0].size());
  std::vector<int8_t> v(w * h);
  std::vector<uint8_t> f(w * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const char c = rows_top_first[j][i];
      const std::size_t idx = static_cast<std::size_t>(h - 1 - j) * w + i;
      v[idx] = c == '.' ? 0 : (c == '#' ? 100 : -1);
      f[idx] = c == '.';
    }
  return OccupancyGrid(w, h, res, origin, v, f);
}

TEST(OccupancyGrid, WorldCellRoundTrip) {
  const OccupancyGrid g = make_grid({"....", "....", "...."});
  EXPECT_EQ(g.world_to_cell({1.0, -2.0}), (Cell{0, 0}));
  EXPECT_EQ(g.world_to_cell({1.49, -1.51}), (Cell{0, 0}));
  EXPECT_EQ(g.world_to_cell({1.5, -1.5}), (Cell{1, 1}));
  EXPECT_EQ(g.world_to_cell({0.99, -2.0}), (Cell{0, -1}));
  EXPECT_FALSE(g.contains(g.world_to_cell({0.99, -2.0})));
  const Point2 c = g.cell_center({2, 3});
  EXPECT_DOUBLE_EQ(c.x, 1.0 + 3.5 * 0.5);
  EXPECT_DOUBLE_EQ(c.y, -2.0 + 2.5 * 0.5);
  EXPECT_EQ(g.world_to_cell(c), (Cell{2, 3}));
}

TEST(OccupancyGrid, RowZeroIsBottomOfImage) {
  const OccupancyGrid g = make_grid({"#...", "....", "...."});
  EXPECT_FALSE(g.is_free({2, 0}));
  EXPECT_TRUE(g.is_free({0, 0}));
}

TEST(OccupancyGrid, RejectsBadSizes) {
  EXPECT_THROW(OccupancyGrid(2, 2, 0.0, {}, std::vector<int8_t>(4), std::vector<uint8_t>(4)), std::invalid_argument);
  EXPECT_THROW(OccupancyGrid(2, 2, 1.0, {}, std::vector<int8_t>(3), std::vector<uint8_t>(4)), std::invalid_argument);
}

TEST(Reachability, UnknownAndWallsSplitComponents) {
  const OccupancyGrid g = make_grid({"..#..", "..?..", "..#.."});
  const auto mask = reachable_from(g, {0, 0});
  EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 6);
  EXPECT_EQ(mask[g.index({1, 3})], 0);
  const FreeSpaceSummary s = summarize_free_space(g, {0, 0});
  EXPECT_EQ(s.free_cells, 12u);
  EXPECT_EQ(s.reachable_cells, 6u);
  EXPECT_EQ(s.other_components, 1u);
  EXPECT_EQ(s.largest_other_cells, 6u);
}

TEST(Reachability, StartOnObstacleReachesNothing) {
  const OccupancyGrid g = make_grid({".#."});
  const auto mask = reachable_from(g, {0, 1});
  EXPECT_EQ(std::count(mask.begin(), mask.end(), 1), 0);
}

}  // namespace
}  // namespace gather

#include "gather_core/grid/planning_grid.hpp"

namespace gather {
namespace {

TEST(PlanningGrid, CoarseningKeepsThinWallsAndUnknownSpace) {
  // A one-cell wall between two rooms, a door two cells wide, unknown corner.
  const OccupancyGrid g =
      make_grid({"....#...", "....#...", "........", "........", "....#...", "....#.??"}, 0.5, {0.0, 0.0});
  const OccupancyGrid c = coarsen(g, 2);
  ASSERT_EQ(c.width(), 4);
  ASSERT_EQ(c.height(), 3);
  EXPECT_DOUBLE_EQ(c.resolution(), 1.0);
  // Blocks holding a wall cell are occupied: the wall stays, 2 blocks thick.
  EXPECT_FALSE(c.is_free(Cell{2, 2}));
  EXPECT_EQ(c.value(Cell{2, 2}), 100);
  EXPECT_FALSE(c.is_free(Cell{0, 2}));
  EXPECT_TRUE(c.is_free(Cell{1, 2}));   // the door is still open
  EXPECT_FALSE(c.is_free(Cell{0, 3}));  // unknown cells are never free
  EXPECT_EQ(c.value(Cell{0, 3}), -1);
  EXPECT_TRUE(c.is_free(Cell{0, 0}));
}

TEST(PlanningGrid, BlocksStickingOutOfTheMapAreNotFree) {
  const OccupancyGrid g = make_grid({".....", ".....", "....."}, 0.5, {0.0, 0.0});
  const OccupancyGrid c = coarsen(g, 2);
  ASSERT_EQ(c.width(), 3);
  ASSERT_EQ(c.height(), 2);
  EXPECT_TRUE(c.is_free(Cell{0, 0}));
  EXPECT_FALSE(c.is_free(Cell{0, 2}));  // column 4 plus a missing column
  EXPECT_FALSE(c.is_free(Cell{1, 0}));  // row 2 plus a missing row
}

TEST(PlanningGrid, FactorFollowsMaxCellsAndBacksOffWhenADoorWouldClose) {
  // 40 x 20 open room: 800 cells; at most 200 cells -> factor 2.
  const OccupancyGrid open = make_grid(std::vector<std::string>(20, std::string(40, '.')), 0.1, {0.0, 0.0});
  EXPECT_EQ(choose_planning_grid(open, Point2{0.05, 0.05}, 0).factor, 1);
  EXPECT_EQ(choose_planning_grid(open, Point2{0.05, 0.05}, 1000).factor, 1);
  EXPECT_EQ(choose_planning_grid(open, Point2{0.05, 0.05}, 200).factor, 2);
  EXPECT_EQ(choose_planning_grid(open, Point2{0.05, 0.05}, 50).factor, 4);
  // A wall across the middle with a door one cell wide at an odd row: any
  // coarsening closes it and loses half the space, so the map's grid is kept.
  std::vector<std::string> rows(20, std::string(40, '.'));
  for (int r = 0; r < 20; ++r) rows[static_cast<std::size_t>(r)][20] = '#';
  rows[9][20] = '.';
  const OccupancyGrid door = make_grid(rows, 0.1, {0.0, 0.0});
  const PlanningGrid pg = choose_planning_grid(door, Point2{0.05, 0.05}, 200);
  EXPECT_EQ(pg.factor, 1);
  EXPECT_DOUBLE_EQ(choose_planning_grid(open, Point2{0.05, 0.05}, 200).kept, 1.0);
  // The OC's block must be free: a post next to the OC keeps the map's grid.
  std::vector<std::string> post(20, std::string(40, '.'));
  post[19][1] = '#';  // bottom row, next to the OC's cell (0, 0)
  EXPECT_EQ(choose_planning_grid(make_grid(post, 0.1, {0.0, 0.0}), Point2{0.05, 0.05}, 200).factor, 1);
}

}  // namespace
}  // namespace gather
