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

// 6 m x 4 m with a wall at x = 3 m from the north edge down to y = 0.5 m:
// the way from the west half to the east half goes round its south end.
// The OC in the west half's north-west corner.
Scenario walled() {
  Scenario s = testing_support::open_strip("walled", 60, 40, Point2{0.25, 3.75});
  std::vector<int8_t> v(60 * 40, 0);
  std::vector<uint8_t> f(60 * 40, 1);
  for (int r = 5; r < 40; ++r)
    v[static_cast<std::size_t>(r) * 60 + 30] = 100, f[static_cast<std::size_t>(r) * 60 + 30] = 0;
  s.grid = OccupancyGrid(60, 40, 0.1, Point2{0, 0}, v, f);
  return s;
}

TEST(HomeWalksTest, KeptOrMarchedAloneAWalkIsTheWholeMapsMarch) {
  const Scenario scenario = walled();
  const PlanContext ctx{scenario};
  // A segment in the east half's north-east, and a home in the west half's north.
  std::vector<Cell> cells;
  for (int r = 34; r < 40; ++r)
    for (int c = 45; c < 60; ++c) cells.push_back(Cell{r, c});
  const Cell home{39, 20};
  fmm::FastMarching whole = ctx.coverage_field;
  fmm::SolveOptions so;
  so.labels = false;
  whole.solve({fmm::Source::at_cell(home)}, so);
  std::vector<double> expected;
  for (Cell c : cells) expected.push_back(whole.time(c));
  ASSERT_GT(expected.front(), 2 * 3.4) << "the walk goes round the wall's south end";

  fmm::FastMarching walk = ctx.coverage_field;
  HomeWalks kept(std::size_t{1} << 30), alone(0);
  std::vector<double> first, again, marched;
  kept.distances(home, cells, walk, first);
  kept.distances(home, cells, walk, again);  // from the kept field
  alone.distances(home, cells, walk, marched);
  EXPECT_EQ(first, expected);
  EXPECT_EQ(again, expected);
  EXPECT_EQ(marched, expected);
  EXPECT_EQ(kept.kept(), 1u);
  EXPECT_EQ(kept.marched(), 1u);
  EXPECT_EQ(alone.kept(), 0u);
  EXPECT_EQ(alone.marched(), 1u);
}

TEST(HomeWalksTest, ASegmentsHomeWalkIsMarchedOnTheWholeMap) {
  const Scenario scenario = walled();
  const PlanContext ctx{scenario};
  // Segment 1: the west half; segment 2: the east half.
  LabelImage labels(scenario.grid.frame());
  std::vector<Cell> east;
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 60; ++c)
      if (scenario.grid.is_free(Cell{r, c})) {
        labels.at(Cell{r, c}) = c < 30 ? 1 : 2;
        if (c >= 30) east.push_back(Cell{r, c});
      }
  WorkerGraph graph = build_worker_graph(scenario.grid, labels, 2, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
  segment_distances(ctx, labels, graph, PlannerOptions{});
  const Cell home = ctx.oc_worker_home(east);
  ASSERT_GE(home.row, 0);
  fmm::FastMarching whole = ctx.coverage_field;
  fmm::SolveOptions so;
  so.labels = false;
  whole.solve({fmm::Source::at_cell(home)}, so);
  double sum = 0.0;
  for (Cell c : east) sum += whole.time(c);
  EXPECT_NEAR(graph.segment(SegmentId(2)).mean_home_distance, sum / static_cast<double>(east.size()), 1e-9);
  EXPECT_GE(ctx.home_walks->kept(), 1u);
}

}  // namespace
}  // namespace plan
}  // namespace gather
