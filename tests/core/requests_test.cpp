// mission/requests: the goals the OC draws, cycle after cycle.
#include "gather_core/mission/requests.hpp"

#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

#include "corridor.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace mission {
namespace {

TEST(RequestsTest, CycleMajorOnReachableFreeCells) {
  Scenario s = testing_support::corridor();
  // Wall off the far end (columns 150-199): its cells are free but not reachable.
  std::vector<int8_t> v = s.grid.values();
  std::vector<uint8_t> f = s.grid.free_mask();
  for (int r = 0; r < s.grid.height(); ++r) v[s.grid.index(Cell{r, 149})] = 100, f[s.grid.index(Cell{r, 149})] = 0;
  s.grid = OccupancyGrid(s.grid.width(), s.grid.height(), 0.1, Point2{0, 0}, v, f);
  const World world(s);
  const std::vector<DrawnGoal> goals = draw_goals(world, 7, 4, 50);
  ASSERT_EQ(goals.size(), 200u);
  for (std::size_t i = 0; i < goals.size(); ++i) {
    EXPECT_EQ(goals[i].cycle, static_cast<int>(i / 50)) << "goal " << i;
    EXPECT_TRUE(world.reachable[s.grid.index(goals[i].cell)]) << "goal " << i;
    EXPECT_LT(goals[i].cell.col, 149);
  }
}

TEST(RequestsTest, TheSeedDecidesAndOnlyTheSeed) {
  const Scenario s = testing_support::corridor();
  const World world(s);
  auto cells = [&](unsigned seed) {
    std::vector<std::pair<int, int>> out;
    for (const DrawnGoal& g : draw_goals(world, seed, 3, 40)) out.emplace_back(g.cell.row, g.cell.col);
    return out;
  };
  EXPECT_EQ(cells(1), cells(1));
  EXPECT_NE(cells(1), cells(2));
  // Spread over the corridor, not bunched: 120 draws over 1000 cells hit many distinct columns.
  std::set<int> cols;
  for (const auto& c : cells(3)) cols.insert(c.second);
  EXPECT_GT(cols.size(), 60u);
}

TEST(RequestsTest, EmptyAndBadRequests) {
  const Scenario s = testing_support::corridor();
  const World world(s);
  EXPECT_TRUE(draw_goals(world, 1, 0, 10).empty());
  EXPECT_TRUE(draw_goals(world, 1, 5, 0).empty());
  EXPECT_THROW(draw_goals(world, 1, -1, 10), Error);
  EXPECT_THROW(draw_goals(world, 1, 2, -3), Error);
}

}  // namespace
}  // namespace mission
}  // namespace gather
