// mission/world: on the corridor (tests/core/corridor.hpp) by hand: the
// reachable space, the OC's coverage (x < 2.6 m), its border, the way back
// into it, where a worker of the OC waits for requests, where a robot stands
// (a pose off the free space) and the homes of workers of the OC on robots.
#include "gather_core/mission/world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/grid/clearance.hpp"

namespace gather {
namespace {

using testing_support::corridor;

TEST(WorldTest, TheCorridorsCoverageAndTheWayBackByHand) {
  const Scenario s = corridor();
  const mission::World w(s);
  EXPECT_EQ(w.oc_cell, (Cell{2, 5}));
  EXPECT_EQ(w.reachable_cells, 1000u);
  EXPECT_NEAR(w.reachable_area, 10.0, 1e-9);  // 20 m x 0.5 m
  // Covered: cell centres within the 2.07 m range of the OC at x = 0.55 m.
  for (int c = 0; c < 200; ++c) {
    const double x = 0.05 + 0.1 * c;
    const bool in = w.covered(Cell{2, c});
    if (x < 2.5) {
      EXPECT_TRUE(in) << x;
    } else if (x > 2.7) {
      EXPECT_FALSE(in) << x;
    }
  }
  EXPECT_FALSE(w.covered(Cell{-1, 0}));  // off the map
  // The border: covered cells next to an uncovered one or the map's edge;
  // the far end of the coverage is among them.
  bool far_end = false;
  for (Cell b : w.coverage_border) {
    EXPECT_TRUE(w.covered(b));
    far_end = far_end || (b.row == 2 && !w.covered(Cell{2, b.col + 1}));
  }
  EXPECT_TRUE(far_end);
  // The way back from x = 10.05 m is 10.05 - 2.55 = 7.5 m, to a border cell.
  const Cell far{2, 100};
  EXPECT_NEAR(w.coverage_field.time(far), 7.5, 0.15);
  const int label = w.coverage_field.label(far);
  ASSERT_GE(label, 0);
  EXPECT_NEAR(s.grid.cell_center(w.coverage_border[static_cast<std::size_t>(label)]).x, 2.55, 0.11);
}

TEST(WorldTest, AWorkerOfTheOcWaitsWhereItsSegmentMeetsTheCoverage) {
  const Scenario s = corridor();
  const mission::World w(s);
  // A segment beyond the coverage (x from 5 m): it waits at the coverage's
  // far end, where it comes back to from the segment's nearest cell.
  std::vector<Cell> far;
  for (int c = 50; c < 60; ++c) far.push_back(Cell{2, c});
  const Cell home = w.oc_worker_home(far);
  EXPECT_TRUE(w.covered(home));
  EXPECT_NEAR(s.grid.cell_center(home).x, 2.55, 0.11);
  // A segment that is partly covered: its own nearest covered cell (the
  // first in row-major order at distance 0).
  const std::vector<Cell> across{Cell{1, 20}, Cell{1, 21}, Cell{1, 40}};
  EXPECT_EQ(w.oc_worker_home(across), (Cell{1, 20}));
  EXPECT_EQ(w.oc_worker_home({}), (Cell{-1, -1}));
}

TEST(WorldTest, AWalledInOcIsRefusedNamingTheScenario) {
  Scenario s = corridor();
  std::vector<int8_t> v(s.grid.values());
  std::vector<uint8_t> f(s.grid.free_mask());
  const std::size_t oc = s.grid.index(s.grid.world_to_cell(s.oc));
  v[oc] = 100, f[oc] = 0;  // the OC stands on a wall
  s.grid = OccupancyGrid(200, 5, 0.1, Point2{0, 0}, v, f);
  try {
    const mission::World w(s);
    FAIL() << "a world with nothing reachable was built";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("corridor: no free space is reachable from the OC"), std::string::npos)
        << e.what();
  }
}

// The corridor with cells set occupied (blocked: rows r0..r1, cols c0..c1).
Scenario corridor_with_block(int r0, int r1, int c0, int c1) {
  Scenario s = corridor();
  std::vector<int8_t> v(s.grid.values());
  std::vector<uint8_t> f(s.grid.free_mask());
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) {
      const std::size_t i = s.grid.index(Cell{r, c});
      v[i] = 100, f[i] = 0;
    }
  s.grid = OccupancyGrid(200, 5, 0.1, Point2{0, 0}, v, f);
  return s;
}

TEST(WorldTest, ARobotStandsOnItsOwnCellOrTheNearestReachableOne) {
  const Scenario s = corridor();
  const mission::World w(s);
  // On the free space: its own cell.
  EXPECT_EQ(w.standing_cell(Point2{5.05, 0.25}), (Cell{2, 50}));
  EXPECT_EQ(w.standing_cell(Point2{0.01, 0.49}), (Cell{4, 0}));
  // 0.15 m below the map (row -2): the first ring holding a reachable cell
  // is the second, and (0, 50) is its nearest.
  EXPECT_EQ(w.standing_cell(Point2{5.05, -0.15}), (Cell{0, 50}));
  // Past the east end (column 202): (2, 199), three columns back.
  EXPECT_EQ(w.standing_cell(Point2{20.25, 0.25}), (Cell{2, 199}));
  // 0.45 m below (row -5): five rings; a radius of 0.45 m looks that far,
  // 0.35 m (four rings) does not, and the robot's own cell comes back,
  // which the caller finds unreachable.
  EXPECT_EQ(w.standing_cell(Point2{5.05, -0.45}, 0.45), (Cell{0, 50}));
  const Cell short_of = w.standing_cell(Point2{5.05, -0.45}, 0.35);
  EXPECT_EQ(short_of, (Cell{-5, 50}));
  EXPECT_FALSE(w.reaches(short_of));
  // Far off (a localisation gone wild): its own cell, not reachable.
  const Cell far = w.standing_cell(Point2{-1000.0, -1000.0});
  EXPECT_EQ(far, (Cell{-10000, -10000}));
  EXPECT_FALSE(w.reaches(far));
}

TEST(WorldTest, ARobotOnAnObstacleStandsOnTheNearestReachableCellFirstInRowMajorOrder) {
  // A 0.3 m x 0.3 m block (rows 1-3, cols 50-52) in the middle of the
  // corridor: rows 0 and 4 pass it.
  const Scenario s = corridor_with_block(1, 3, 50, 52);
  const mission::World w(s);
  ASSERT_FALSE(w.reaches(Cell{2, 51}));
  // On the block's centre: ring 1 is all block; in ring 2, (0, 51), (4, 51),
  // (2, 49) and (2, 53) are 2 cells away; (0, 51) is the first in row-major order.
  EXPECT_EQ(w.standing_cell(s.grid.cell_center(Cell{2, 51})), (Cell{0, 51}));
  // On the block's west edge: (2, 49), one cell away.
  EXPECT_EQ(w.standing_cell(s.grid.cell_center(Cell{2, 50})), (Cell{2, 49}));
  // On its north-east corner: (3, 53) and (4, 52) are one cell away;
  // (3, 53) comes first.
  EXPECT_EQ(w.standing_cell(s.grid.cell_center(Cell{3, 52})), (Cell{3, 53}));
}

TEST(WorldTest, AFreeCellCutOffFromTheOcIsNotWhereARobotStands) {
  // Walls across the corridor at columns 100 and 102: column 101 is free
  // but cut off, as is everything east of it.
  Scenario s = corridor_with_block(0, 4, 100, 100);
  {
    std::vector<int8_t> v(s.grid.values());
    std::vector<uint8_t> f(s.grid.free_mask());
    for (int r = 0; r < 5; ++r) {
      const std::size_t i = s.grid.index(Cell{r, 102});
      v[i] = 100, f[i] = 0;
    }
    s.grid = OccupancyGrid(200, 5, 0.1, Point2{0, 0}, v, f);
  }
  const mission::World w(s);
  ASSERT_TRUE(s.grid.free_mask()[s.grid.index(Cell{2, 101})]);
  ASSERT_FALSE(w.reaches(Cell{2, 101}));
  // Standing in the pocket: the nearest reachable cell, west of the wall.
  EXPECT_EQ(w.standing_cell(s.grid.cell_center(Cell{2, 101})), (Cell{2, 99}));
  // East of the walls, more than 2 m from anything reachable: its own cell.
  EXPECT_EQ(w.standing_cell(s.grid.cell_center(Cell{2, 150})), (Cell{2, 150}));
  EXPECT_FALSE(w.reaches(Cell{2, 150}));
}

TEST(WorldTest, HomesOnRobotsHaveRoomInTheCoverageAndStandApart) {
  // An open 10 m x 6 m floor, the OC at its west edge: the coverage is the
  // half disc of 2 m around it. Three segments east of it, out of the
  // coverage, share one plain home on its east border.
  Scenario s = testing_support::open_strip("floor", 100, 60, Point2{0.55, 3.05});
  const mission::World w(s);
  std::vector<std::vector<Cell>> segments(3);
  for (int k = 0; k < 3; ++k)  // x from 7, 8 and 9 m, y 2.5-3.5 m
    for (int r = 25; r < 35; ++r)
      for (int c = 70 + 10 * k; c < 80 + 10 * k; ++c) segments[static_cast<std::size_t>(k)].push_back(Cell{r, c});
  const Cell plain = w.oc_worker_home(segments[0]);
  ASSERT_TRUE(w.covered(plain));
  // One plain home for the three: the coverage's east tip.
  ASSERT_EQ(w.oc_worker_home(segments[1]), plain);
  ASSERT_EQ(w.oc_worker_home(segments[2]), plain);
  // No room asked: the plain homes.
  const std::vector<Cell> same = w.oc_worker_homes(segments, 0.0);
  ASSERT_EQ(same.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(same[static_cast<std::size_t>(k)], w.oc_worker_home(segments[k]));
  // 0.5 m of room inside the coverage, 1 m apart.
  std::vector<int8_t> cv(s.grid.size(), 100);
  std::vector<uint8_t> cf(s.grid.size(), 0);
  for (std::size_t i = 0; i < s.grid.size(); ++i)
    if (w.coverage[i]) cv[i] = 0, cf[i] = 1;
  const OccupancyGrid coverage_only(100, 60, 0.1, Point2{0, 0}, cv, cf);
  const ClearanceMap room(coverage_only);  // room inside the coverage
  const std::vector<Cell> homes = w.oc_worker_homes(segments, 0.5);
  ASSERT_EQ(homes.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(w.covered(homes[k])) << k;
    EXPECT_GE(room.at(homes[k]), 0.5) << k;
    for (std::size_t j = 0; j < k; ++j) {
      const Point2 a = s.grid.cell_center(homes[k]), b = s.grid.cell_center(homes[j]);
      EXPECT_GE(std::hypot(a.x - b.x, a.y - b.y), 1.0) << k << " " << j;
    }
  }
  // The first is the nearest such cell to the plain home: within the room
  // it needs (plus a cell's diagonal) of it.
  const Point2 h = s.grid.cell_center(homes[0]), p = s.grid.cell_center(plain);
  EXPECT_LE(std::hypot(h.x - p.x, h.y - p.y), 0.5 + 0.15);
  // More room than the coverage holds (it is 2 m deep): the room halves
  // until it fits; every home still in the coverage, all of them apart.
  const std::vector<Cell> crowded = w.oc_worker_homes(segments, 4.0);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(w.covered(crowded[k])) << k;
    EXPECT_GE(room.at(crowded[k]), 0.5) << k;  // 4 -> 2 -> 1 -> 0.5 m at the most
    for (std::size_t j = 0; j < k; ++j) EXPECT_NE(crowded[k], crowded[j]);
  }
  // The same homes every time (each agent computes them for itself).
  EXPECT_EQ(w.oc_worker_homes(segments, 0.5), homes);
  // A segment that reaches no coverage has no home.
  Scenario walled = s;
  std::vector<int8_t> v(100 * 60, 0);
  std::vector<uint8_t> f(100 * 60, 1);
  for (int r = 0; r < 60; ++r)
    v[static_cast<std::size_t>(r) * 100 + 50] = 100, f[static_cast<std::size_t>(r) * 100 + 50] = 0;
  walled.grid = OccupancyGrid(100, 60, 0.1, Point2{0, 0}, v, f);
  const mission::World ww(walled);
  EXPECT_EQ(ww.oc_worker_homes({segments[0]}, 0.5)[0], (Cell{-1, -1}));
}

}  // namespace
TEST(WorldTest, HomesOnRobotsKeepOffTheLaneOutOfTheCoverage) {
  // A 2.5 m x 5 m room, the OC in its middle, and one corridor 1.2 m wide
  // (y 1.9-3.1 m) east out of it to x = 8 m: the coverage (2 m around the
  // OC) ends 0.75 m into the corridor. Four segments down the corridor
  // leave the coverage by it. A robot parked in the corridor or its mouth
  // stands in the way of every other one: the homes keep off the lane
  // (the corridor's middle, out into the room while it is narrow, and
  // 0.3 m + two radii either side of it), in the room.
  const Scenario s = testing_support::room_with_corridor(4);
  const mission::World w(s);
  std::vector<std::vector<Cell>> segments(4);
  for (int k = 0; k < 4; ++k)  // x 4.5-5, 5.5-6, ... down the corridor
    for (int r = 19; r <= 30; ++r)
      for (int c = 45 + 10 * k; c < 50 + 10 * k; ++c) segments[static_cast<std::size_t>(k)].push_back(Cell{r, c});
  const Cell plain = w.oc_worker_home(segments[0]);
  ASSERT_TRUE(w.covered(plain));
  ASSERT_GE(plain.col, 25);  // the coverage's tip in the corridor
  const std::vector<Cell> homes = w.oc_worker_homes(segments, 1.0);
  ASSERT_EQ(homes.size(), 4u);
  for (std::size_t k = 0; k < homes.size(); ++k) {
    const Point2 h = s.grid.cell_center(homes[k]);
    EXPECT_TRUE(w.covered(homes[k])) << k;
    EXPECT_LT(h.x, 2.5) << k << ": a home in the corridor, at x " << h.x;
    // Off the lane where it leaves the room (by 0.7 m, less a cell).
    if (h.x > 1.25) {
      EXPECT_GE(std::abs(h.y - 2.5), 0.6) << k << ": a home in the corridor's mouth, at " << h.x << " " << h.y;
    }
    for (std::size_t j = 0; j < k; ++j) EXPECT_NE(homes[k], homes[j]);
  }
  EXPECT_EQ(w.oc_worker_homes(segments, 1.0), homes);
}

}  // namespace gather
