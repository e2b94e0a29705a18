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
