// mission/world: on the corridor (tests/core/corridor.hpp) by hand: the
// reachable space, the OC's coverage (x < 2.6 m), its border, the way back
// into it, and where a worker of the OC waits for requests.
#include "gather_core/mission/world.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "corridor.hpp"
#include "gather_core/error.hpp"

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

}  // namespace
}  // namespace gather
