// plan/estimate: the planner's estimate of refresh time and delivered goals,
// against hand-made segments, routes and the simulator.
#include "gather_core/plan/estimate.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/world.hpp"
#include "gather_core/plan/planner.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

// Thousands of goals per request: the binomial goal count of a segment must
// not underflow ((1 - p)^G is 0 in double precision here), or the estimate
// would credit its worker with no goals at all.
TEST(PlanEstimateTest, ManyGoalsPerRequestAreNotLostToUnderflow) {
  Scenario s = testing_support::small_office();
  s.mission.goals_per_request = 6000;
  const plan::PlanContext ctx(s);
  const auto cfg = plan::plan_configuration(ctx, partition::Method::kBap, 0);
  for (const auto& w : cfg.estimates.workers) EXPECT_GT(w.delivered_goals, 1.0) << "segment " << w.segment;
  // Far fewer than 6000 are measured: only what fits in a request period
  // after the request reached the worker (mission::request_deadline).
  EXPECT_GT(cfg.estimates.goals, 40.0);
  EXPECT_LE(cfg.estimates.goals, 6000.0 + 1e-6);
}

// The corridor (tests/core/corridor.hpp: 20 m x 0.5 m, coverage x < 2.6 m,
// 1 m/s) with one worker of the OC owning all of it, one goal a request.
Scenario corridor_alone(double period, int cycles) {
  Scenario s = testing_support::corridor();
  s.team.agents = 1;
  s.mission.goals_per_request = 1;
  s.mission.period = period;
  s.mission.cycles = cycles;
  return s;
}

TEST(PlanEstimateTest, AnOcWorkersTourStartsAtItsHomeAndWalksOnTheMap) {
  const Scenario s = corridor_alone(100.0, 10);
  const plan::PlanContext ctx(s);
  const auto cfg = plan::plan_configuration(ctx, partition::Method::kBap, 0);
  ASSERT_EQ(cfg.graph.segments.size(), 1u);
  const plan::WorkerSegment& seg = cfg.graph.segment(SegmentId(1));
  // Home: the first covered cell of the segment (row-major), at x = 0.05;
  // the goal is uniform over x in [0, 20]: 10 m out on average, and back to
  // the coverage (x < 2.6) 17.4^2 / 2 / 20 = 7.57 m.
  EXPECT_NEAR(seg.mean_home_distance, 9.95, 0.3);
  EXPECT_NEAR(seg.mean_coverage_distance, 7.57, 0.3);
  // Two uniform points of a 20 m line lie 20 / 3 m apart on average (an
  // open square of the same area: 0.52 sqrt(10) = 1.65 m).
  EXPECT_NEAR(seg.mean_pair_distance, 20.0 / 3.0, 0.3);
  ASSERT_EQ(seg.home_quantiles.size(), 17u);
  EXPECT_NEAR(seg.home_quantiles[8], 10.0, 0.3);  // the median cell
  // The simulator's latency by hand: walk out x, back max(0, x - 2.55):
  // 10 + 7.57 s (the old model, twice the distance to the coverage: 15.1 s).
  ASSERT_EQ(cfg.estimates.workers.size(), 1u);
  EXPECT_NEAR(cfg.estimates.workers[0].refresh_s, 17.5, 0.6);
  EXPECT_NEAR(cfg.estimates.workers[0].delivered_goals, 1.0, 1e-6);
}

TEST(PlanEstimateTest, AGoalFartherThanAPeriodsWalkIsNeverMeasured) {
  // A period of 10 s and one cycle: the worker learns request 0 at the OC's
  // cell (x = 0.55), where it starts, and measures the goal when it lies
  // within 10 m of there: x < 10.55, 52.75% of the corridor (a trip from
  // its home at x = 0.05 would give 50.25%).
  const Scenario s = corridor_alone(10.0, 1);
  const plan::PlanContext ctx(s);
  const auto cfg = plan::plan_configuration(ctx, partition::Method::kBap, 0);
  ASSERT_EQ(cfg.estimates.workers.size(), 1u);
  // From x = 0.55: (0.55^2 + 19.45^2) / 2 / 20 = 9.47 m on average.
  EXPECT_NEAR(cfg.graph.segment(SegmentId(1)).mean_oc_distance, 9.47, 0.3);
  EXPECT_NEAR(cfg.estimates.workers[0].delivered_goals, 0.5275, 0.01);
}

TEST(PlanEstimateTest, AnOcWorkersHomeIsTheCoverageCellNearestItsSegment) {
  const Scenario s = testing_support::corridor();  // coverage: x < 2.6 m, columns 0-25
  const mission::World world(s);
  std::vector<Cell> far, touching;
  for (int r = 0; r < s.grid.height(); ++r)
    for (int c = 0; c < s.grid.width(); ++c) {
      if (c >= 100) far.push_back(Cell{r, c});
      if (c >= 20 && c < 50) touching.push_back(Cell{r, c});
    }
  // Far from the coverage: where the way back from its nearest cell (row 0,
  // column 100, first of the ties in row-major order) enters the coverage.
  const Cell home = world.oc_worker_home(far);
  EXPECT_TRUE(world.covered(home));
  EXPECT_EQ(home.col, 25);
  // Overlapping the coverage: its first covered cell in row-major order.
  const Cell inside = world.oc_worker_home(touching);
  EXPECT_EQ(inside.row, 0);
  EXPECT_EQ(inside.col, 20);
  EXPECT_EQ(world.oc_worker_home({}).row, -1);
}

TEST(PlanEstimateTest, IntervalOfUncertainDeliveries) {
  const double horizon = 1000.0;
  plan::AreaDeliveries sure;
  for (int i = 0; i < 10; ++i) sure.delivery(100.0 + 50.0 * i, 1.0);
  EXPECT_NEAR(sure.interval(horizon), 50.0, 1e-9);  // every delivery happens: (last - first) / 9
  plan::AreaDeliveries one;
  one.delivery(100.0, 1.0);
  EXPECT_DOUBLE_EQ(one.interval(horizon), horizon);  // fewer than two: the whole mission
  // Ten chances of 1/2: D ~ B(10, 1/2); by hand, horizon (P0 + P1) =
  // 1000 * 11 / 1024 = 10.74, and S = 11 * 450 / 9 = 550 times
  // E[1 / (D + 1); D >= 2] = (1 - 2^-11) / 5.5 - 1/1024 - 10 / 2048 = 0.175870.
  plan::AreaDeliveries half;
  for (int i = 0; i < 10; ++i) half.delivery(100.0 + 50.0 * i, 0.5);
  EXPECT_NEAR(half.interval(horizon), 10.742 + 550.0 * 0.175870, 0.01);
  // Rare deliveries are mostly fewer than two: close to the whole mission.
  plan::AreaDeliveries rare;
  for (int i = 0; i < 10; ++i) rare.delivery(100.0 + 50.0 * i, 0.01);
  EXPECT_GT(rare.interval(horizon), 0.99 * horizon);
  // A tile split between two segments sums its parts.
  plan::AreaDeliveries tile;
  tile.merge(sure), tile.merge(one);
  EXPECT_DOUBLE_EQ(tile.events, 11.0);
  EXPECT_NEAR(tile.interval(horizon), 45.0, 1e-9);
}

TEST(PlanEstimateTest, NearestShareOfAnAreaPart) {
  plan::AreaDeliveries near, far;
  for (int b = 0; b < plan::AreaDeliveries::kRankBins / 2; ++b) near.rank_out[static_cast<std::size_t>(b)] = 3.0f;
  for (int b = plan::AreaDeliveries::kRankBins / 2; b < plan::AreaDeliveries::kRankBins; ++b)
    far.rank_out[static_cast<std::size_t>(b)] = 3.0f;
  EXPECT_DOUBLE_EQ(plan::AreaDeliveries::nearest_share(near.rank_out, 0.25), 0.5);
  EXPECT_DOUBLE_EQ(plan::AreaDeliveries::nearest_share(near.rank_out, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(plan::AreaDeliveries::nearest_share(far.rank_out, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(plan::AreaDeliveries::nearest_share(far.rank_out, 0.75), 0.5);
  EXPECT_DOUBLE_EQ(plan::AreaDeliveries::nearest_share(far.rank_out, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(plan::AreaDeliveries::nearest_share(near.rank_in, 0.5), 0.0);  // no covered cells
}

}  // namespace
}  // namespace gather
