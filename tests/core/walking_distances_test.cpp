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
  PlannerOptions exact;  // on the planning grid (the pair grid's walks: below)
  exact.pair_grid_factor = 1;
  const PlanContext ctx{scenario, exact}, coarse_ctx{scenario};
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
  WorkerGraph coarse = graph;
  segment_distances(ctx, labels, graph, exact);
  segment_distances(coarse_ctx, labels, coarse, PlannerOptions{});
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
  // On the pair grid the walk goes round the wall's end too (on blocks of
  // 2 x 2 cells, scaled): within 5% of the planning grid's (the blocks turn
  // the corner farther from it: the gap, 5 cells, is 2 blocks).
  ASSERT_EQ(coarse_ctx.pair_grid->factor, 2);
  EXPECT_EQ(coarse_ctx.home_walks->marched(), 0u);
  EXPECT_GE(coarse_ctx.pair_home_walks->marched(), 1u);
  EXPECT_NEAR(coarse.segment(SegmentId(2)).mean_home_distance / graph.segment(SegmentId(2)).mean_home_distance, 1.0,
              0.05);
}

// Four segments: the quadrants of the map (of its free cells).
WorkerGraph quadrants(const Scenario& scenario, const PlanContext& ctx, const PlannerOptions& opt) {
  const OccupancyGrid& g = scenario.grid;
  LabelImage labels(g.frame());
  for (int r = 0; r < g.height(); ++r)
    for (int c = 0; c < g.width(); ++c)
      if (g.is_free(Cell{r, c}))
        labels.at(Cell{r, c}) = 1 + (r >= g.height() / 2 ? 2 : 0) + (c >= g.width() / 2 ? 1 : 0);
  WorkerGraph graph = build_worker_graph(g, labels, 4, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
  segment_distances(ctx, labels, graph, opt);
  return graph;
}

TEST(PairGridTest, AnOpenFloorsPairsAreMarchedOnBlocksAndScaledToThePlanningGrid) {
  Scenario scenario = testing_support::open_strip("floor", 80, 60, Point2{0.25, 0.25});
  scenario.team.agents = 4;  // the scale is measured over about a segment's size: these quadrants'
  PlannerOptions exact;
  exact.pair_grid_factor = 1;
  const PlanContext ctx{scenario}, fine_ctx{scenario, exact};
  const PairGrid& pg = *ctx.pair_grid;
  ASSERT_EQ(pg.factor, 2);
  EXPECT_EQ(pg.grid.width(), 40);
  EXPECT_EQ(pg.grid.height(), 30);
  EXPECT_DOUBLE_EQ(pg.grid.resolution(), 0.2);
  EXPECT_EQ(pg.block_of[scenario.grid.index(Cell{5, 7})], static_cast<int32_t>(pg.grid.index(Cell{2, 3})));
  // A first-order march on cells twice as large runs longer: the scale is
  // under 1, by a few percent.
  EXPECT_LT(pg.scale, 1.0) << pg.scale;
  EXPECT_GT(pg.scale, 0.95);
  // On the coarse grid the OC's march starts from its block's centre, half
  // a cell from the OC's cell, here into the floor: its times are a little
  // shorter, and this scale a little over 1.
  EXPECT_GT(pg.walk_scale, 1.0);
  EXPECT_LT(pg.walk_scale, 1.05);
  EXPECT_EQ(fine_ctx.pair_grid->factor, 1);
  const WorkerGraph coarse = quadrants(scenario, ctx, PlannerOptions{});
  const WorkerGraph fine = quadrants(scenario, fine_ctx, exact);
  for (SegmentId k : segment_ids(4)) {
    const double a = coarse.segment(k).mean_pair_distance, b = fine.segment(k).mean_pair_distance;
    EXPECT_NE(a, b) << "segment " << k.label() << " was marched on the planning grid";
    EXPECT_NEAR(a / b, 1.0, 0.01) << "segment " << k.label() << " scale " << pg.scale;
    // The homes' walks too, with their own scale; the walk from the OC's
    // cell is the context's (on the planning grid) either way.
    const double h = coarse.segment(k).mean_home_distance, hf = fine.segment(k).mean_home_distance;
    EXPECT_NE(h, hf) << "segment " << k.label() << "'s home walk was marched on the planning grid";
    EXPECT_NEAR(h / hf, 1.0, 0.02) << "segment " << k.label() << " walk scale " << pg.walk_scale;
    EXPECT_EQ(coarse.segment(k).mean_oc_distance, fine.segment(k).mean_oc_distance);
  }
}

// pair_grid_factor 3 and 4 (the range's top): blocks of 3 x 3 and 4 x 4
// cells, measured on the quadrants of an open floor against the planning
// grid: the pairs within 1% once scaled, the homes' walks within 10%.
TEST(PairGridTest, FactorsThreeAndFourMarchOnLargerBlocks) {
  Scenario scenario = testing_support::open_strip("floor", 84, 60, Point2{0.25, 0.25});
  scenario.team.agents = 4;
  PlannerOptions exact;
  exact.pair_grid_factor = 1;
  const PlanContext fine_ctx{scenario, exact};
  const WorkerGraph fine = quadrants(scenario, fine_ctx, exact);
  for (const int f : {3, 4}) {
    PlannerOptions opt;
    opt.pair_grid_factor = f;
    const PlanContext ctx{scenario, opt};
    const PairGrid& pg = *ctx.pair_grid;
    ASSERT_EQ(pg.factor, f);
    EXPECT_EQ(pg.grid.width(), 84 / f);
    EXPECT_EQ(pg.grid.height(), 60 / f);
    EXPECT_DOUBLE_EQ(pg.grid.resolution(), 0.1 * f);
    EXPECT_EQ(pg.block_of[scenario.grid.index(Cell{13, 22})],
              static_cast<int32_t>(pg.grid.index(Cell{13 / f, 22 / f})));
    EXPECT_LT(pg.scale, 1.0) << "factor " << f;
    EXPECT_GT(pg.scale, 0.9) << "factor " << f;
    const WorkerGraph coarse = quadrants(scenario, ctx, opt);
    for (SegmentId k : segment_ids(4)) {
      const double a = coarse.segment(k).mean_pair_distance, b = fine.segment(k).mean_pair_distance;
      const double h = coarse.segment(k).mean_home_distance, hf = fine.segment(k).mean_home_distance;
      EXPECT_NE(a, b) << "factor " << f << ", segment " << k.label() << " was marched on the planning grid";
      EXPECT_NE(h, hf) << "factor " << f << ", segment " << k.label() << "'s home walk on the planning grid";
      // Pairs 0.993-0.999 of the planning grid's (unscaled they would be
      // 1.3-1.7% over it); homes 0.92-1.02: the OC's own quadrant, whose
      // walks are short, farthest (blocks of 0.3-0.4 m round the home).
      EXPECT_NEAR(a / b, 1.0, 0.01) << "factor " << f << ", segment " << k.label() << ", scale " << pg.scale;
      EXPECT_NEAR(h / hf, 1.0, 0.1) << "factor " << f << ", segment " << k.label() << ", walk scale " << pg.walk_scale;
    }
  }
}

TEST(PairGridTest, ACellOfABlockThatIsNotFreeStandsOnTheNearestReachableBlock) {
  const Scenario scenario = walled();  // a one-cell wall in column 30
  const PlanContext ctx{scenario};
  const PairGrid& pg = *ctx.pair_grid;
  ASSERT_EQ(pg.factor, 2);
  auto block_of = [&](Cell c) {
    const int32_t b = pg.block_of[scenario.grid.index(c)];
    return b < 0 ? Cell{-1, -1} : pg.grid.cell(static_cast<std::size_t>(b));
  };
  EXPECT_EQ(block_of(Cell{10, 29}), (Cell{5, 14}));  // its own block
  // Column 31's blocks hold the wall: the cell stands on the block east of
  // it (its centre 1.5 cells away, not the west one's 2.5), its own side.
  EXPECT_EQ(block_of(Cell{10, 31}), (Cell{5, 16}));
  EXPECT_EQ(pg.block_of[scenario.grid.index(Cell{10, 30})], -1);  // the wall
}

// Two segments of `scenario` (label_of(cell), 1 or 2, on its free cells):
// their walking distances on the pair grid (the default options) and on
// the planning grid (pair_grid_factor 1).
struct TwoWays {
  int factor = 0;  // the pair grid's
  WorkerGraph coarse, fine;
};
template <class LabelOf>
TwoWays two_ways(const Scenario& scenario, LabelOf label_of) {
  PlannerOptions exact;
  exact.pair_grid_factor = 1;
  const PlanContext ctx{scenario}, fine_ctx{scenario, exact};
  LabelImage labels(scenario.grid.frame());
  for (int r = 0; r < scenario.grid.height(); ++r)
    for (int c = 0; c < scenario.grid.width(); ++c)
      if (scenario.grid.is_free(Cell{r, c})) labels.at(Cell{r, c}) = label_of(Cell{r, c});
  TwoWays out;
  out.factor = ctx.pair_grid->factor;
  out.coarse = build_worker_graph(scenario.grid, labels, 2, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
  out.fine = out.coarse;
  segment_distances(ctx, labels, out.coarse, PlannerOptions{});
  segment_distances(fine_ctx, labels, out.fine, exact);
  return out;
}

TEST(PairGridTest, ASegmentAlongAWallStartsFromTheBlocksStandingForItsCells) {
  // Segment 2: column 31 along `walled`'s wall, rows 5-39, whose blocks hold
  // the wall: its pair sources start from the blocks east of them (one
  // wide column of them); segment 1: the rest.
  const TwoWays w = two_ways(walled(), [](Cell c) { return c.col == 31 && c.row >= 5 ? 2 : 1; });
  ASSERT_EQ(w.factor, 2);
  for (SegmentId k : segment_ids(2)) {
    const double a = w.coarse.segment(k).mean_pair_distance, b = w.fine.segment(k).mean_pair_distance;
    EXPECT_NE(a, b) << "segment " << k.label() << " was marched on the planning grid";
    EXPECT_NEAR(a / b, 1.0, 0.05) << "segment " << k.label();
  }
}

// 4 m x 6 m: a room (rows 12-59), and a corridor one cell wide in row 10
// between walls in rows 9 and 11, open to the room at its west end only
// (cell (11, 0)); rows 0-8 are wall. The OC in the room.
Scenario corridor_over_a_room() {
  Scenario s = testing_support::open_strip("corridor", 40, 60, Point2{2.05, 3.05});
  std::vector<int8_t> v(40 * 60, 100);
  std::vector<uint8_t> f(40 * 60, 0);
  auto open = [&](int r, int c) {
    v[static_cast<std::size_t>(r) * 40 + c] = 0, f[static_cast<std::size_t>(r) * 40 + c] = 1;
  };
  for (int r = 12; r < 60; ++r)
    for (int c = 0; c < 40; ++c) open(r, c);
  for (int c = 0; c < 40; ++c) open(10, c);
  open(11, 0);
  s.grid = OccupancyGrid(40, 60, 0.1, Point2{0, 0}, v, f);
  return s;
}

TEST(PairGridTest, ACellNeverStandsOnABlockAcrossAWall) {
  const Scenario scenario = corridor_over_a_room();
  const PlanContext ctx{scenario};
  const PairGrid& pg = *ctx.pair_grid;
  ASSERT_EQ(pg.factor, 2) << "the room keeps over 95% of the space";
  // The corridor's blocks hold the walls; the room's block under a
  // corridor cell is nearest, but behind the wall of row 11.
  EXPECT_EQ(pg.block_of[scenario.grid.index(Cell{10, 20})], -1);
  // At the corridor's open end the cell walks into the room's block.
  EXPECT_EQ(pg.block_of[scenario.grid.index(Cell{10, 0})], static_cast<int32_t>(pg.grid.index(Cell{6, 0})));
}

TEST(PairGridTest, ASegmentOfCellsOnNoBlockIsMarchedOnThePlanningGrid) {
  // Segment 2: the corridor (its cells but the open end stand on no block):
  // its home walk and pair distances on the planning grid, exactly; segment
  // 1, the room, on the pair grid.
  const TwoWays w = two_ways(corridor_over_a_room(), [](Cell c) { return c.row <= 11 ? 2 : 1; });
  ASSERT_EQ(w.factor, 2);
  const WorkerSegment& corridor = w.coarse.segment(SegmentId(2));
  ASSERT_EQ(corridor.home_quantiles.size(), 17u) << "the corridor's worker walks from a home";
  EXPECT_EQ(corridor.mean_home_distance, w.fine.segment(SegmentId(2)).mean_home_distance);
  EXPECT_EQ(corridor.home_quantiles, w.fine.segment(SegmentId(2)).home_quantiles);
  EXPECT_EQ(corridor.mean_pair_distance, w.fine.segment(SegmentId(2)).mean_pair_distance);
  EXPECT_NE(w.coarse.segment(SegmentId(1)).mean_pair_distance, w.fine.segment(SegmentId(1)).mean_pair_distance);
}

TEST(PairGridTest, AGridThatWouldCloseADoorIsNotUsed) {
  // Two rooms of 4 m x 4 m, a wall two cells thick between them and a door
  // one cell wide: on blocks of 2 x 2 cells the east room is cut off.
  Scenario scenario = testing_support::open_strip("rooms", 82, 40, Point2{0.25, 0.25});
  std::vector<int8_t> v(82 * 40, 0);
  std::vector<uint8_t> f(82 * 40, 1);
  for (int r = 0; r < 40; ++r)
    for (int c = 40; c < 42; ++c)
      if (r != 21) v[static_cast<std::size_t>(r) * 82 + c] = 100, f[static_cast<std::size_t>(r) * 82 + c] = 0;
  scenario.grid = OccupancyGrid(82, 40, 0.1, Point2{0, 0}, v, f);
  const PlanContext ctx{scenario};
  EXPECT_EQ(ctx.pair_grid->factor, 1);
  EXPECT_TRUE(ctx.pair_grid->block_of.empty());
}

}  // namespace
}  // namespace plan
}  // namespace gather
