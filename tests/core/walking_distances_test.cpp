// plan/walking_distances: a segment's walking distances (from its worker's
// home, from the OC's cell, between its cells) and the ranks of its cells,
// on a one-cell-wide strip where every distance is a count of cells.
#include "gather_core/plan/walking_distances.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <vector>

#include "corridor.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/plan/worker_graph.hpp"

namespace gather {
namespace plan {
namespace {

constexpr double kCell = 0.1;  // [m]

// 10 m x 0.1 m: 100 cells in a row, the OC in cell 0. Segment 1 holds
// columns 0-49 (it overlaps the OC's coverage), segment 2 columns 50-99.
struct Strip {
  Scenario scenario = testing_support::open_strip("strip", 100, 1, Point2{0.05, 0.05});
  PlanContext ctx{scenario};
  LabelImage labels{scenario.grid.frame()};
  WorkerGraph graph;
  Field rank;
  Strip() {
    for (int c = 0; c < 100; ++c) labels.at(Cell{0, c}) = c < 50 ? 1 : 2;
    graph = build_worker_graph(scenario.grid, labels, 2, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
    rank = segment_distances(ctx, labels, graph, PlannerOptions{});
  }
};

// Mean over the columns c0..c1 of |c - from| cells [m].
double mean_walk(int from, int c0, int c1) {
  double sum = 0.0;
  for (int c = c0; c <= c1; ++c) sum += std::abs(c - from) * kCell;
  return sum / (c1 - c0 + 1);
}

TEST(WalkingDistancesTest, FromTheHomeAndFromTheOcByHand) {
  const Strip s;
  const WorkerSegment& far = s.graph.segment(SegmentId(2));
  std::vector<Cell> cells;
  for (int c = 50; c < 100; ++c) cells.push_back(Cell{0, c});
  const Cell home = s.ctx.oc_worker_home(cells);
  ASSERT_EQ(home.row, 0);
  ASSERT_TRUE(s.ctx.covered(home));
  ASSERT_FALSE(s.ctx.covered(Cell{0, home.col + 1})) << "the home is the coverage's last cell towards segment 2";
  EXPECT_NEAR(far.mean_home_distance, mean_walk(home.col, 50, 99), 1e-4);
  EXPECT_NEAR(far.mean_oc_distance, mean_walk(0, 50, 99), 1e-4);  // 7.45 m
  // Quantile i: the distance at rank i / 16 of the 50 cells, ascending.
  ASSERT_EQ(far.home_quantiles.size(), 17u);
  for (std::size_t i = 0; i <= 16; ++i) {
    const int col = 50 + static_cast<int>(std::min<std::size_t>(49, i * 50 / 16));
    EXPECT_NEAR(far.home_quantiles[i], (col - home.col) * kCell, 1e-4) << i;
    EXPECT_NEAR(far.oc_quantiles[i], col * kCell, 1e-4) << i;
  }
}

TEST(WalkingDistancesTest, PairsFromSourcesSpreadOverTheSegment) {
  const Strip s;
  // pair_sources = 3 of 50 cells: positions 8, 25 and 41 (the middles of
  // three equal runs), each to all 50 cells.
  const double expected = (mean_walk(8, 0, 49) + mean_walk(25, 0, 49) + mean_walk(41, 0, 49)) / 3.0;
  EXPECT_NEAR(s.graph.segment(SegmentId(2)).mean_pair_distance, expected, 1e-4);
  EXPECT_NEAR(s.graph.segment(SegmentId(1)).mean_pair_distance, expected, 1e-4);
}

TEST(WalkingDistancesTest, CellsRankByTheirWalkFromTheHome) {
  const Strip s;
  EXPECT_EQ(s.rank.frame(), s.scenario.grid.frame());
  // Segment 2: its cells in order of distance from the home, column 50 first.
  for (int c = 50; c < 100; ++c) EXPECT_NEAR(s.rank.at(Cell{0, c}), (c - 50) / 50.0, 1e-6) << c;
  for (float r : s.rank) {
    EXPECT_GE(r, 0.0f);
    EXPECT_LT(r, 1.0f);
  }
}

}  // namespace
}  // namespace plan
}  // namespace gather
