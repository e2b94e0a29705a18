// plan/planner: the sweep, its routes, its options and their ranges.
#include "gather_core/plan/planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

class PlannerTest : public testing_support::SmallOfficeTest {};

TEST_F(PlannerTest, RoutesAreClosedClearAndStartInCoverage) {
  for (partition::Method m : partition::all_methods()) {
    const auto cfg = plan::plan_configuration(*ctx_, m, 2);
    ASSERT_EQ(cfg.routes.size(), 2u);
    for (const auto& r : cfg.routes) {
      if (r.segments.empty()) continue;
      ASSERT_GE(r.waypoints.size(), 2u);
      const Point2 a = r.waypoints.front(), b = r.waypoints.back();
      EXPECT_NEAR(a.x, b.x, 1e-9);
      EXPECT_NEAR(a.y, b.y, 1e-9);
      EXPECT_TRUE(ctx_->coverage[scenario_->grid.index(scenario_->grid.world_to_cell(a))]);
      EXPECT_GE(r.min_clearance, scenario_->team.radius - 1e-9) << partition::method_name(m);
      for (const Point2& p : r.waypoints) EXPECT_TRUE(scenario_->grid.is_free(scenario_->grid.world_to_cell(p)));
      EXPECT_NEAR(r.period, r.length / scenario_->team.speed, 1e-9);
      EXPECT_FALSE(r.coverage_entries.empty());
      for (const auto& meeting : r.meetings) EXPECT_FALSE(meeting.passes.empty());
    }
  }
}

TEST_F(PlannerTest, SweepUtilitiesAreInUnitRangeAndTheBestIsTheMaximum) {
  const auto sweep = plan::sweep(*ctx_);
  ASSERT_EQ(sweep.configs.size(), 3u * 4u);
  double best = -1;
  for (const auto& c : sweep.configs) {
    EXPECT_GE(c.utility, 0.0);
    EXPECT_LE(c.utility, 1.0);
    best = std::max(best, c.utility);
  }
  EXPECT_EQ(sweep.configs[static_cast<std::size_t>(sweep.best)].utility, best);
  EXPECT_EQ(sweep.threads, plan::PlannerOptions{}.threads);  // a small map: every thread asked for fits
}

TEST_F(PlannerTest, BadRequestsAreClearErrors) {
  EXPECT_THROW(plan::plan_configuration(*ctx_, partition::Method::kBap, 8), Error);  // no worker left
  EXPECT_THROW(plan::plan_configuration(*ctx_, partition::Method::kBap, -1), Error);
  Scenario boxed = testing_support::small_office();
  // Wall the OC into a single cell: nothing else is reachable.
  const Cell oc = boxed.grid.world_to_cell(boxed.oc);
  std::vector<int8_t> v = boxed.grid.values();
  std::vector<uint8_t> f = boxed.grid.free_mask();
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc)
      if (dr || dc) {
        const std::size_t i = boxed.grid.index(Cell{oc.row + dr, oc.col + dc});
        v[i] = 100, f[i] = 0;
      }
  boxed.grid = OccupancyGrid(boxed.grid.width(), boxed.grid.height(), 0.1, Point2{0, 0}, v, f);
  const plan::PlanContext tiny(boxed);
  EXPECT_EQ(tiny.reachable_cells, 1u);
  try {
    plan::plan_configuration(tiny, partition::Method::kPap, 2);
    FAIL() << "6 workers in 1 reachable cell must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("reachable"), std::string::npos) << e.what();
  }
}

// The planner's memory budget (docs/input_limits.md): fewer threads when
// more would not fit, and a planning grid too large for one refused up
// front, naming what to lower.
TEST(PlanBudget, ThreadsShrinkToTheBudgetAndAGridTooLargeForOneThreadIsRefused) {
  Scenario s;
  s.path = "big.yaml";
  s.team.agents = 20;
  auto grid_of = [](int w, int h) {
    const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    return OccupancyGrid(w, h, 0.05, Point2{0, 0}, std::vector<int8_t>(n, 0), std::vector<uint8_t>(n, 1));
  };
  s.grid = grid_of(2000, 1000);  // 2M cells: both threads
  EXPECT_EQ(plan::threads_within_budget(s, 2, 27), 2);
  EXPECT_LE(plan::plan_memory_bytes(s.grid.size(), 20, 2, 27), kMemoryBudget);
  s.grid = grid_of(2000, 2000);  // 4M cells: one thread
  EXPECT_EQ(plan::threads_within_budget(s, 2, 27), 1);
  s.team.agents = 400;  // the square of the team, per thread
  EXPECT_GT(plan::plan_memory_bytes(s.grid.size(), 400, 1, 1), plan::plan_memory_bytes(s.grid.size(), 20, 1, 1) + 70e6);
  s.grid = grid_of(5000, 4000);  // 20M cells: not even one configuration
  try {
    plan::threads_within_budget(s, 2, 1);
    FAIL() << "accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("big.yaml: planning would take about", 0), 0u) << what;
    EXPECT_NE(what.find("20000000 cells"), std::string::npos) << what;
    EXPECT_NE(what.find("planner.max_cells"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

// BAP orders its wavefronts by the context's march from the OC: the very
// times of the march it would run itself, so the same partitions.
TEST_F(PlannerTest, TheContextsMarchFromTheOcIsBapsOwn) {
  const OccupancyGrid& grid = scenario_->grid;
  fmm::FastMarching fm(grid);
  fmm::SolveOptions so;
  so.labels = false;
  fm.solve({fmm::Source::at_cell(ctx_->oc_cell)}, so);
  EXPECT_EQ(ctx_->prepared.oc_distance, fm.times());
  partition::PreparedArea alone = ctx_->prepared;
  alone.oc_distance = Raster<double>();
  EXPECT_EQ(partition::partition_area(grid, ctx_->prepared, partition::Method::kBap, 7).labels,
            partition::partition_area(grid, alone, partition::Method::kBap, 7).labels);
}

TEST_F(PlannerTest, OptionsOutsideTheirRangeNameTheField) {
  plan::PlannerOptions opt;
  opt.pair_sources = 0;
  try {
    plan::plan_configuration(*ctx_, partition::Method::kBap, 2, opt);
    FAIL() << "pair_sources = 0 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pair_sources = 0 must be in [1, 64]"), std::string::npos) << e.what();
  }
  opt = plan::PlannerOptions{};
  opt.pair_grid_factor = 5;
  try {
    plan::check_options(opt);
    FAIL() << "pair_grid_factor = 5 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pair_grid_factor = 5 must be in [1, 4]"), std::string::npos) << e.what();
  }
  // The context is built with the pair grid's factor: another is refused.
  opt = plan::PlannerOptions{};
  opt.pair_grid_factor = 1;
  try {
    plan::plan_configuration(*ctx_, partition::Method::kBap, 2, opt);
    FAIL() << "pair_grid_factor = 1 was accepted by a context built with 2";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pair_grid_factor = 1 is not the one the plan context was built with (2)"),
              std::string::npos)
        << e.what();
  }
  opt = plan::PlannerOptions{};
  opt.tsp_constant = std::nan("");
  EXPECT_THROW(plan::check_options(opt), Error);
  EXPECT_NO_THROW(plan::check_options(plan::PlannerOptions{}));
  opt = plan::PlannerOptions{};
  opt.pass_radius_m = 0.05;
  EXPECT_THROW(plan::check_options(opt), Error);
}

// Every tuning field of PlannerOptions is refused out of its range with one
// line naming it, and changes what it says it changes (none is dead).
TEST_F(PlannerTest, TheTuningFieldsHaveRangesAndEachChangesThePlan) {
  const struct {
    const char* message;
    void (*set)(plan::PlannerOptions&);
  } bad[] = {
      {"pass_step_m = 0.01 must be in [0.05, 5] m", [](plan::PlannerOptions& o) { o.pass_step_m = 0.01; }},
      {"pass_probe_m = 2 must be in [0.01, 1] m", [](plan::PlannerOptions& o) { o.pass_probe_m = 2.0; }},
      {"tight_speed = 0 must be in [0.001, 1]", [](plan::PlannerOptions& o) { o.tight_speed = 0.0; }},
      {"contact_step_m = 0 must be in [0.05, 5] m", [](plan::PlannerOptions& o) { o.contact_step_m = 0.0; }},
      {"lateness_bins = 4 must be in [8, 4096]", [](plan::PlannerOptions& o) { o.lateness_bins = 4; }},
      {"delivery_samples = 0 must be in [1, 256]", [](plan::PlannerOptions& o) { o.delivery_samples = 0; }},
      {"area_goal_samples = 300 must be in [1, 256]", [](plan::PlannerOptions& o) { o.area_goal_samples = 300; }},
      {"window_margin_m = -1 must be in [0, 100] m", [](plan::PlannerOptions& o) { o.protocol.window_margin_m = -1; }},
      {"two_opt_rounds = -1 must be in [0, 10000]", [](plan::PlannerOptions& o) { o.protocol.two_opt_rounds = -1; }},
      {"exact_route_stops = 17 must be in [0, 16]", [](plan::PlannerOptions& o) { o.exact_route_stops = 17; }},
  };
  for (const auto& b : bad) {
    plan::PlannerOptions opt;
    b.set(opt);
    try {
      plan::check_options(opt);
      ADD_FAILURE() << b.message << ": accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(b.message), std::string::npos) << e.what();
    }
  }
  // A context is built with its tight_speed: options with another are refused.
  plan::PlannerOptions tight;
  tight.tight_speed = 0.5;
  EXPECT_THROW(plan::plan_configuration(*ctx_, partition::Method::kBap, 1, tight), Error);

  // Each field moves the plan of the grown groups (collectors at work, and
  // workers of the OC): its routes or its estimates.
  plan::PlannerOptions base;
  base.associate = false;
  auto fingerprint = [](const plan::ConfigurationPlan& c) {
    std::vector<double> f{c.estimates.refresh_s, c.estimates.interval_s, c.estimates.goals};
    for (const plan::CollectorRoute& r : c.routes) {
      f.push_back(r.length);
      for (const plan::MeetingArea& m : r.meetings) f.insert(f.end(), m.passes.begin(), m.passes.end());
    }
    return f;
  };
  const auto reference = fingerprint(plan::plan_configuration(*ctx_, partition::Method::kPap, 2, base));
  const struct {
    const char* field;
    void (*set)(plan::PlannerOptions&);
  } changes[] = {
      {"pass_step_m", [](plan::PlannerOptions& o) { o.pass_step_m = 2.0; }},
      {"pass_probe_m", [](plan::PlannerOptions& o) { o.pass_probe_m = 0.6; }},
      {"contact_step_m", [](plan::PlannerOptions& o) { o.contact_step_m = 3.0; }},
      {"lateness_bins", [](plan::PlannerOptions& o) { o.lateness_bins = 8; }},
      {"delivery_samples", [](plan::PlannerOptions& o) { o.delivery_samples = 1; }},
      {"area_goal_samples", [](plan::PlannerOptions& o) { o.area_goal_samples = 1; }},
      {"exact_route_stops", [](plan::PlannerOptions& o) { o.exact_route_stops = 0; }},
      {"protocol.window_margin_m", [](plan::PlannerOptions& o) { o.protocol.window_margin_m = 0.0; }},
  };
  for (const auto& c : changes) {
    plan::PlannerOptions opt = base;
    c.set(opt);
    EXPECT_NE(fingerprint(plan::plan_configuration(*ctx_, partition::Method::kPap, 2, opt)), reference) << c.field;
  }
  // tight_speed: the routes' speed where the robot does not fit (next to
  // walls; this office's routes never need to squeeze through).
  const plan::PlanContext squeeze(*scenario_, tight);
  std::size_t tight_cells = 0;
  for (std::size_t i = 0; i < squeeze.route_speed.size(); ++i)
    if (squeeze.reachable[i] && !squeeze.roomy[i]) {
      ++tight_cells;
      EXPECT_EQ(squeeze.route_speed[i], 0.5);
      EXPECT_EQ(ctx_->route_speed[i], 0.05);
    }
  EXPECT_GT(tight_cells, 0u);
}

TEST_F(PlannerTest, ThePassRadiusDecidesWhereARoutePassesNextToASegment) {
  // The grown groups (routes that serve segments). With a 10 cm radius a
  // stretch is where the route runs over the segment's own cells: still
  // found (not only the meeting point, the fallback), but elsewhere.
  plan::PlannerOptions grown, narrow;
  grown.associate = narrow.associate = false;
  narrow.pass_radius_m = 0.1;
  const auto base = plan::plan_configuration(*ctx_, partition::Method::kPap, 2, grown);
  const auto far = plan::plan_configuration(*ctx_, partition::Method::kPap, 2, narrow);
  std::size_t passes_base = 0, passes_far = 0, found_far = 0;
  bool differ = false;
  ASSERT_EQ(base.routes.size(), far.routes.size());
  for (CollectorId r : ids<CollectorId>(base.routes.count()))
    for (std::size_t m = 0; m < base.routes[r].meetings.size() && m < far.routes[r].meetings.size(); ++m) {
      passes_base += base.routes[r].meetings[m].passes.size();
      passes_far += far.routes[r].meetings[m].passes.size();
      differ = differ || base.routes[r].meetings[m].passes != far.routes[r].meetings[m].passes;
      const plan::MeetingArea& narrow_meeting = far.routes[r].meetings[m];
      found_far += narrow_meeting.passes != std::vector<double>{narrow_meeting.arc_m};
    }
  EXPECT_GT(passes_base, 0u);
  EXPECT_GT(passes_far, 0u);
  EXPECT_GT(found_far, 0u) << "a 10 cm radius finds no stretch over any served segment";
  EXPECT_TRUE(differ) << "a 10 cm radius gives the same passes as a 1 m one";
}

}  // namespace
}  // namespace gather
