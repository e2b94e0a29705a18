// path/grid_astar: shortest 8-connected paths by A*, by hand on small grids.
#include "gather_core/path/grid_astar.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "predicate_grid.hpp"

namespace gather {
namespace {

OccupancyGrid open_grid(int w, int h) {
  return testing_support::predicate_grid(
      w, h, [](int, int) { return true; }, 0.1);
}

// Every step goes to one of the 8 neighbours, onto a traversable cell, and
// a diagonal step never passes a blocked corner.
void expect_valid(const std::vector<Cell>& path, const OccupancyGrid& g, const Mask& free) {
  auto ok = [&](Cell c) { return g.contains(c) && free[g.index(c)] != 0; };
  for (std::size_t i = 0; i < path.size(); ++i) {
    EXPECT_TRUE(ok(path[i])) << "cell " << i;
    if (i == 0) continue;
    const int dr = path[i].row - path[i - 1].row, dc = path[i].col - path[i - 1].col;
    EXPECT_TRUE(std::abs(dr) <= 1 && std::abs(dc) <= 1 && (dr || dc)) << "step " << i;
    if (dr && dc) {
      EXPECT_TRUE(ok(Cell{path[i - 1].row + dr, path[i - 1].col}) && ok(Cell{path[i - 1].row, path[i - 1].col + dc}))
          << "diagonal step " << i << " past a blocked corner";
    }
  }
}

TEST(GridAStarTest, OpenGridTakesTheOctileShortestPath) {
  const OccupancyGrid g = open_grid(10, 10);
  const Mask free(g.frame(), 1);
  GridAStar astar(g, free);
  std::vector<Cell> path;
  ASSERT_TRUE(astar.find(Cell{0, 0}, Cell{5, 3}, path));
  ASSERT_EQ(path.size(), 6u);  // 3 diagonal + 2 straight steps
  EXPECT_EQ(path.front().row, 0);
  EXPECT_EQ(path.front().col, 0);
  EXPECT_EQ(path.back().row, 5);
  EXPECT_EQ(path.back().col, 3);
  expect_valid(path, g, free);
  ASSERT_TRUE(astar.find(Cell{4, 4}, Cell{4, 4}, path));
  EXPECT_EQ(path.size(), 1u);
}

TEST(GridAStarTest, AroundAWallThroughItsDoorWithoutCuttingCorners) {
  // 9 x 9, a wall along column 4 with a door at row 8 (the top row).
  const OccupancyGrid g = open_grid(9, 9);
  Mask free(g.frame(), 1);
  for (int r = 0; r < 8; ++r) free[g.index(Cell{r, 4})] = 0;
  GridAStar astar(g, free);
  std::vector<Cell> path;
  ASSERT_TRUE(astar.find(Cell{0, 0}, Cell{0, 8}, path));
  expect_valid(path, g, free);
  bool door = false;
  for (const Cell& c : path) door = door || (c.row == 8 && c.col == 4);
  EXPECT_TRUE(door);
  // (0, 0) -> (8, 3): 8 steps; through the door (8, 3) -> (8, 4) -> (8, 5):
  // 2, straight, since (7, 4) blocks the diagonals; (8, 5) -> (0, 8): 8.
  // 18 steps, 19 cells.
  EXPECT_EQ(path.size(), 19u);
}

TEST(GridAStarTest, UnreachableOrBlockedEndsGiveAnEmptyPath) {
  const OccupancyGrid g = open_grid(9, 9);
  Mask free(g.frame(), 1);
  for (int r = 0; r < 9; ++r) free[g.index(Cell{r, 4})] = 0;  // no door
  GridAStar astar(g, free);
  std::vector<Cell> path{Cell{1, 1}};
  EXPECT_FALSE(astar.find(Cell{0, 0}, Cell{0, 8}, path));
  EXPECT_TRUE(path.empty());
  EXPECT_FALSE(astar.find(Cell{0, 4}, Cell{0, 0}, path));   // start in the wall
  EXPECT_FALSE(astar.find(Cell{0, 0}, Cell{0, 4}, path));   // goal in the wall
  EXPECT_FALSE(astar.find(Cell{0, 0}, Cell{-1, 0}, path));  // off the map
}

TEST(GridAStarTest, AWorkspaceReusedPastItsGenerationCounterGivesTheSameAnswers) {
  // The stamps are 16-bit: 70000 searches wrap them more than once.
  const OccupancyGrid g = open_grid(6, 6);
  Mask free(g.frame(), 1);
  free[g.index(Cell{2, 2})] = free[g.index(Cell{2, 3})] = free[g.index(Cell{3, 2})] = 0;
  GridAStar astar(g, free);
  std::vector<Cell> first, path;
  ASSERT_TRUE(astar.find(Cell{0, 0}, Cell{5, 5}, first));
  for (int i = 0; i < 70000; ++i) {
    ASSERT_TRUE(astar.find(i % 2 ? Cell{0, 0} : Cell{5, 0}, i % 2 ? Cell{5, 5} : Cell{0, 5}, path)) << i;
  }
  ASSERT_TRUE(astar.find(Cell{0, 0}, Cell{5, 5}, path));
  EXPECT_EQ(path.size(), first.size());
  expect_valid(path, g, free);
}

// The process's resident memory [bytes], from /proc/self/statm.
double resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  double pages_total = 0, pages_resident = 0;
  statm >> pages_total >> pages_resident;
  return pages_resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

TEST(GridAStarTest, ASearchMakesResidentOnlyThePagesOfTheCellsItReaches) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer keeps shadow memory for every allocation";
#endif
  if (std::getenv("MALLOC_PERTURB_")) GTEST_SKIP() << "MALLOC_PERTURB_ makes calloc write every byte";
  // A robot's agent holds one workspace for the whole map and searches a
  // small part of it: 7 B a cell (63 MB here) must not all become resident.
  const OccupancyGrid g = open_grid(3000, 3000);
  const Mask free(g.frame(), 1);
  const double before = resident_bytes();
  GridAStar astar(g, free);
  std::vector<Cell> path;
  ASSERT_TRUE(astar.find(Cell{0, 0}, Cell{0, 40}, path));
  EXPECT_EQ(path.size(), 41u);
  EXPECT_LT(resident_bytes() - before, 8e6) << "a 41-cell search on a 9M-cell grid";
  ASSERT_TRUE(astar.find(Cell{2999, 2999}, Cell{2990, 2960}, path));  // the far corner: its own pages
  expect_valid(path, g, free);
  EXPECT_LT(resident_bytes() - before, 8e6);
}

TEST(GridAStarTest, AMaskOfAnotherSizeIsRefused) {
  const OccupancyGrid g = open_grid(6, 6);
  EXPECT_THROW(GridAStar(g, Mask(GridFrame{6, 5}, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace gather
