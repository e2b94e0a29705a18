// plan/route_builder: a collector's closed route on the corridor, where its
// length, meeting point, passes and coverage entries can be worked out.
#include "gather_core/plan/route_builder.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/plan/worker_graph.hpp"
#include "small_office.hpp"

namespace gather {
namespace plan {
namespace {

// The corridor (20 m x 0.5 m, the OC at x = 0.55 m, its coverage x < 2.6 m)
// in two segments: 1 = x < 10 m, 2 = the rest.
struct TwoHalves {
  Scenario scenario = testing_support::corridor();
  PlanContext ctx{scenario};
  LabelImage labels{scenario.grid.frame()};
  WorkerGraph graph;
  TwoHalves() {
    for (int r = 0; r < labels.height(); ++r)
      for (int c = 0; c < labels.width(); ++c) labels.at(Cell{r, c}) = c < 100 ? 1 : 2;
    graph = build_worker_graph(scenario.grid, labels, 2, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
  }
  CollectorRoute route(const std::vector<SegmentId>& segments) {
    fmm::FastMarching fm = ctx.oc_field;
    return build_route(ctx, fm, graph, labels, segments, CollectorId(0), PlannerOptions{});
  }
};

TEST(RouteBuilderTest, OutToTheFarHalfAndBack) {
  TwoHalves h;
  const CollectorRoute r = h.route({SegmentId(2)});
  ASSERT_GE(r.waypoints.size(), 2u);
  EXPECT_NEAR(r.waypoints.front().x, 0.55, 1e-9);
  EXPECT_NEAR(r.waypoints.back().x, 0.55, 1e-9);
  ASSERT_EQ(r.segments, std::vector<SegmentId>{SegmentId(2)});
  // Segment 2's entry is its cell nearest the coverage: column 100 (x = 10.05 m).
  const Point2 entry = h.scenario.grid.cell_center(h.graph.segment(SegmentId(2)).entry);
  EXPECT_NEAR(entry.x, 10.05, 1e-9);
  EXPECT_NEAR(r.length, 2.0 * (10.05 - 0.55), 0.3);
  EXPECT_NEAR(r.period, r.length / h.scenario.team.speed, 1e-9);
  ASSERT_EQ(r.meetings.size(), 1u);
  const MeetingArea& m = r.meetings[0];
  EXPECT_EQ(m.segment, SegmentId(2));
  EXPECT_NEAR(m.point.x, 10.05, 0.15);
  EXPECT_NEAR(m.arc_m, 10.05 - 0.55, 0.2);
  // The route runs over segment 2 only around its turn: one stretch.
  ASSERT_EQ(m.passes.size(), 1u);
  EXPECT_NEAR(m.passes[0], m.arc_m, 1.0);
  // Uploads are counted at the first waypoint back inside the coverage: on
  // a straight corridor that is the OC itself, the route's end.
  ASSERT_EQ(r.coverage_entries.size(), 1u);
  EXPECT_DOUBLE_EQ(r.coverage_entries[0], r.length);
  EXPECT_GT(r.min_clearance, 0.0);
}

TEST(RouteBuilderTest, ACollectorWithoutSegmentsStaysAtTheOc) {
  TwoHalves h;
  const CollectorRoute r = h.route({});
  ASSERT_EQ(r.waypoints.size(), 1u);
  EXPECT_NEAR(r.waypoints[0].x, 0.55, 1e-9);
  EXPECT_TRUE(r.meetings.empty());
  EXPECT_EQ(r.length, 0.0);
}

TEST(RouteBuilderTest, ServingBothHalvesMeetsThemInVisitingOrder) {
  TwoHalves h;
  const CollectorRoute r = h.route({SegmentId(1), SegmentId(2)});
  // Both ways round are as long (out to x = 10 m and back): either order,
  // but the meetings follow it and the route's segments name it.
  ASSERT_EQ(r.meetings.size(), 2u);
  ASSERT_EQ(r.segments.size(), 2u);
  EXPECT_NE(r.segments[0], r.segments[1]);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(r.meetings[i].segment, r.segments[i]);
  EXPECT_LE(r.meetings[0].arc_m, r.meetings[1].arc_m);
  // Out and back, plus the step aside to segment 1's entry by the OC.
  EXPECT_NEAR(r.length, 2.0 * (10.05 - 0.55), 1.0);
  for (const MeetingArea& m : r.meetings)
    for (double p : m.passes) {
      EXPECT_GE(p, 0.0);
      EXPECT_LE(p, r.length + 1e-9);
    }
}

// The landmarks' bound is admissible: on the small office (rooms off a
// corridor, where the straight line is a poor bound) A* finds legs of the
// same least cost with it as with the octile distance alone, and pops
// fewer cells.
TEST(RouteBuilderTest, TheLandmarksBoundFindsTheLeastCostPoppingFewerCells) {
  const PlanContext& ctx = testing_support::SmallOffice::context();
  const OccupancyGrid& grid = ctx.scenario.grid;
  std::vector<Point2> free;
  for (std::size_t i = 0; i < grid.size(); ++i)
    if (ctx.route_speed[i] > 0) free.push_back(grid.cell_center(grid.cell(i)));
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, free.size() - 1);
  std::size_t with = 0, without = 0;
  for (int n = 0; n < 60; ++n) {
    const Point2 a = free[pick(rng)], b = free[pick(rng)];
    const double exact = leg_search_cost(ctx, a, b, false, &without);
    ASSERT_TRUE(std::isfinite(exact));
    EXPECT_NEAR(leg_search_cost(ctx, a, b, true, &with), exact, 1e-3 * std::max(1.0, exact)) << n;
  }
  EXPECT_LT(2 * with, without) << "the landmarks popped " << with << " cells, the octile distance " << without;
}

// A route's legs search with landmarks from PlannerOptions::leg_landmarks_team
// robots on; the option is checked.
TEST(RouteBuilderTest, LegsSearchWithLandmarksForLargeTeams) {
  const Scenario& s = testing_support::SmallOffice::scenario();  // 8 robots
  EXPECT_FALSE(PlanContext(s).use_leg_landmarks);
  PlannerOptions opt;
  opt.leg_landmarks_team = 8;
  EXPECT_TRUE(PlanContext(s, opt).use_leg_landmarks);
  opt.leg_landmarks_team = -1;
  EXPECT_THROW(check_options(opt), Error);
}

// The legs' paths are kept for the sweep (LegPaths): planning a
// configuration again on the same context searches no leg anew and gives
// the same routes, as does a context that keeps none (its room used up).
TEST(RouteBuilderTest, KeptLegPathsGiveTheRoutesASearchGives) {
  const Scenario& s = testing_support::SmallOffice::scenario();
  const PlanContext ctx(s);
  PlannerOptions opt;
  opt.associate = false;  // the collector keeps every segment grown into its group: a route through several
  const ConfigurationPlan first = plan_configuration(ctx, partition::Method::kPap, 1, opt);
  std::size_t legs = 0;
  for (const CollectorRoute& r : first.routes) legs += r.segments.size() > 1 ? r.segments.size() - 1 : 0;
  ASSERT_GT(legs, 0u) << "no route with a leg between two meeting areas";
  const std::size_t kept = ctx.leg_paths->cells.size(), searched = ctx.leg_paths->searched;
  ASSERT_GT(kept, 0u);
  ASSERT_GE(searched, kept);
  PlanContext full(s);
  full.leg_paths->bytes = LegPaths::kBytes;
  for (const PlanContext* c : {&ctx, static_cast<const PlanContext*>(&full)}) {
    const ConfigurationPlan again = plan_configuration(*c, partition::Method::kPap, 1, opt);
    ASSERT_EQ(again.routes.size(), first.routes.size());
    for (std::size_t i = 0; i < first.routes.size(); ++i) {
      const CollectorRoute &a = first.routes[CollectorId(static_cast<int>(i))],
                           &b = again.routes[CollectorId(static_cast<int>(i))];
      EXPECT_EQ(a.length, b.length);
      ASSERT_EQ(a.waypoints.size(), b.waypoints.size());
      for (std::size_t w = 0; w < a.waypoints.size(); ++w) {
        EXPECT_EQ(a.waypoints[w].x, b.waypoints[w].x);
        EXPECT_EQ(a.waypoints[w].y, b.waypoints[w].y);
      }
    }
  }
  EXPECT_EQ(ctx.leg_paths->searched, searched);  // nothing searched anew
  EXPECT_EQ(ctx.leg_paths->cells.size(), kept);
  EXPECT_GE(full.leg_paths->searched, kept);   // everything searched again
  EXPECT_TRUE(full.leg_paths->cells.empty());  // nothing kept
  // Each kept path goes from its start to its goal by 8-connected steps at
  // the least cost a search finds.
  const OccupancyGrid& grid = s.grid;
  for (const auto& [ends, cells] : ctx.leg_paths->cells) {
    ASSERT_FALSE(cells.empty());
    EXPECT_EQ(cells.front(), ends.first);
    EXPECT_EQ(cells.back(), ends.second);
    double cost = 0.0;
    for (std::size_t i = 1; i < cells.size(); ++i) {
      const Cell a = grid.cell(cells[i - 1]), b = grid.cell(cells[i]);
      const int dr = std::abs(a.row - b.row), dc = std::abs(a.col - b.col);
      ASSERT_TRUE(std::max(dr, dc) == 1) << "not a step";
      cost += (dr + dc == 2 ? std::sqrt(2.0) : 1.0) * 0.5 *
              (1.0 / ctx.route_speed[cells[i - 1]] + 1.0 / ctx.route_speed[cells[i]]);
    }
    // Both bounds are admissible: either search finds the least cost.
    for (const bool landmarks : {false, true}) {
      const double least = leg_search_cost(ctx, grid.cell_center(grid.cell(ends.first)),
                                           grid.cell_center(grid.cell(ends.second)), landmarks);
      EXPECT_NEAR(cost, least, 1e-3 * std::max(1.0, least)) << (landmarks ? "landmarks" : "octile");
    }
  }
}

// A leg from a cell off the reachable space (the speed map's 0 there: no
// step leaves it) is never found, with either bound.
TEST(RouteBuilderTest, NoLegLeavesACellOffTheReachableSpace) {
  const PlanContext& ctx = testing_support::SmallOffice::context();
  const OccupancyGrid& grid = ctx.scenario.grid;
  std::size_t off = grid.size(), on = grid.size();
  for (std::size_t i = 0; i < grid.size(); ++i) {
    // An off cell with a reachable neighbour: the search would step out of it.
    const Cell c = grid.cell(i);
    if (ctx.reachable[i] || c.col + 1 >= grid.width() || !ctx.reachable[i + 1]) continue;
    off = i, on = i + 1;
    break;
  }
  ASSERT_LT(off, grid.size());
  const Point2 a = grid.cell_center(grid.cell(off)), b = grid.cell_center(grid.cell(on));
  for (const bool landmarks : {false, true}) {
    EXPECT_FALSE(std::isfinite(leg_search_cost(ctx, a, b, landmarks))) << landmarks;
    EXPECT_TRUE(std::isfinite(leg_search_cost(ctx, b, b, landmarks))) << landmarks;
  }
}

}  // namespace
}  // namespace plan
}  // namespace gather
