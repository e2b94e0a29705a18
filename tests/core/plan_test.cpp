#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/world.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/plan/planner.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

class PlanTest : public testing_support::SmallOfficeTest {};

TEST_F(PlanTest, RoutesAreClosedClearAndStartInCoverage) {
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

TEST_F(PlanTest, EveryWorkerIsAssociatedExactlyOnce) {
  for (int nc = 0; nc <= 3; ++nc) {
    const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kPap, nc);
    ASSERT_EQ(static_cast<int>(cfg.collector_of_segment.size()), cfg.workers);
    std::multiset<SegmentId> served;
    for (const auto& r : cfg.routes)
      for (const auto& m : r.meetings) served.insert(m.segment);
    for (SegmentId k : segment_ids(cfg.workers)) {
      const CollectorId c = cfg.collector_of_segment[k];
      ASSERT_GE(c.value(), -1);
      ASSERT_LT(c.value(), nc);
      EXPECT_EQ(served.count(k), c.valid() ? 1u : 0u) << k;
      if (c.valid()) {
        EXPECT_FALSE(cfg.graph.segment(k).touches_coverage);
      }
    }
    ASSERT_EQ(cfg.estimates.workers.size(), static_cast<std::size_t>(cfg.workers));
    EXPECT_GT(cfg.estimates.goals, 0.0);
    EXPECT_LE(cfg.estimates.goals, scenario_->mission.goals_per_request + 1e-9);
  }
}

TEST_F(PlanTest, NoRouteIsLongerThanTheRequestPeriodAndTheDecisionNeverLowersTheScore) {
  // On the office's own period the grown routes are too long (the balance
  // step trims them); with a request every 600 s they fit, and the decision
  // step is then compared with the grown groups.
  Scenario slow = *scenario_;
  slow.mission.period = 600.0;
  const plan::PlanContext slow_ctx(slow);
  int longer_before = 0, compared = 0;
  for (const plan::PlanContext* ctx : {ctx_, &slow_ctx})
    for (partition::Method m : partition::all_methods())
      for (int nc = 1; nc <= 3; ++nc) {
        const auto before = plan::plan_configuration(*ctx, m, nc, plan::grown_groups());
        const auto after = plan::plan_configuration(*ctx, m, nc);
        const bool long_before =
            std::any_of(before.routes.begin(), before.routes.end(),
                        [&](const plan::CollectorRoute& r) { return r.period > ctx->cycle_period * (1 + 1e-9); });
        longer_before += long_before;
        for (const auto& r : after.routes)
          EXPECT_LE(r.period, ctx->cycle_period * (1 + 1e-9)) << partition::method_name(m) << " " << nc;
        if (!long_before) {
          ++compared;
          EXPECT_GE(plan::association_score(*ctx, after.estimates),
                    plan::association_score(*ctx, before.estimates) - 1e-12)
              << partition::method_name(m) << " " << nc;
        }
        // The final routes serve the final association, and the estimate is
        // of that association (no estimate of a move that was undone).
        std::multiset<SegmentId> served;
        for (const auto& r : after.routes)
          for (const auto& meeting : r.meetings) served.insert(meeting.segment);
        for (SegmentId k : segment_ids(after.workers)) {
          const CollectorId c = after.collector_of_segment[k];
          EXPECT_EQ(served.count(k), c.valid() ? 1u : 0u);
          EXPECT_EQ(after.estimates.workers[k.index()].collector, c);
        }
      }
  EXPECT_GT(longer_before, 0) << "the grown groups never make a route longer than the period: nothing was tested";
  EXPECT_GT(compared, 0) << "no configuration without a long route: the score was never compared";
}

// A 60 m corridor with the OC at its west end and a request every 200 s: the
// east half is a far segment. By latency, a collector driving 58 m to bring
// it the request and take its data back delivers later than its worker
// walking back itself: the decision gives it to the OC (and the collector
// idles).
Scenario corridor60(RefreshMetric metric) {
  Scenario s = testing_support::open_strip("corridor60", 600, 10, Point2{0.55, 0.5});  // ~2 m of coverage
  s.team.agents = 3;
  s.team.radius = 0.1;
  s.mission.period = 200.0;
  s.mission.goals_per_request = 10;
  s.planner.collectors_min = 0, s.planner.collectors_max = 1;
  s.planner.refresh = metric;
  return s;
}

TEST(PlanAssociationTest, AFarSegmentCheaperFromTheOcGoesToTheOc) {
  const Scenario s = corridor60(RefreshMetric::kLatency);
  const plan::PlanContext ctx(s);
  plan::PlannerOptions grown;
  grown.associate = false;
  const auto before = plan::plan_configuration(ctx, partition::Method::kBap, 1, grown);
  SegmentId far;
  for (SegmentId k : segment_ids(before.workers))
    if (before.collector_of_segment[k] == CollectorId(0)) far = k;
  ASSERT_TRUE(far.valid()) << "the grown groups give the collector no segment";
  ASSERT_LE(before.routes[CollectorId(0)].period, ctx.cycle_period);
  const auto after = plan::plan_configuration(ctx, partition::Method::kBap, 1);
  EXPECT_EQ(after.collector_of_segment[far], CollectorId());
  EXPECT_TRUE(after.routes[CollectorId(0)].segments.empty());
  EXPECT_GT(plan::association_score(ctx, after.estimates), plan::association_score(ctx, before.estimates));
  EXPECT_LT(after.estimates.refresh_s, before.estimates.refresh_s);
}

TEST_F(PlanTest, NoCollectorsSendsEveryWorkerToTheOc) {
  const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kBap, 0);
  EXPECT_TRUE(cfg.routes.empty());
  for (CollectorId c : cfg.collector_of_segment) EXPECT_FALSE(c.valid());
  for (const auto& w : cfg.estimates.workers) EXPECT_FALSE(w.collector.valid());
}

TEST_F(PlanTest, SweepUtilitiesAreInUnitRangeAndTheBestIsTheMaximum) {
  const auto sweep = plan::sweep(*ctx_);
  ASSERT_EQ(sweep.configs.size(), 3u * 4u);
  double best = -1;
  for (const auto& c : sweep.configs) {
    EXPECT_GE(c.utility, 0.0);
    EXPECT_LE(c.utility, 1.0);
    best = std::max(best, c.utility);
  }
  EXPECT_EQ(sweep.configs[static_cast<std::size_t>(sweep.best)].utility, best);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST_F(PlanTest, SameSeedSamePlanAndFileRoundTrip) {
  const auto a = plan::plan_configuration(*ctx_, partition::Method::kRap, 2);
  const auto b = plan::plan_configuration(*ctx_, partition::Method::kRap, 2);
  EXPECT_EQ(a.partition.labels, b.partition.labels);
  const std::string dir = ::testing::TempDir() + "/gather_plan_test";
  std::filesystem::create_directories(dir);
  plan::write_plan_file(dir + "/a.yaml", plan::make_plan_file(*ctx_, a, "labels.png", 1));
  plan::write_plan_file(dir + "/b.yaml", plan::make_plan_file(*ctx_, b, "labels.png", 1));
  EXPECT_EQ(slurp(dir + "/a.yaml"), slurp(dir + "/b.yaml"));

  const plan::PlanFile read = plan::read_plan_file(dir + "/a.yaml");
  plan::write_plan_file(dir + "/c.yaml", read);
  EXPECT_EQ(slurp(dir + "/a.yaml"), slurp(dir + "/c.yaml"));
  EXPECT_EQ(read.method, "rap");
  EXPECT_EQ(read.collectors, 2);
  ASSERT_EQ(read.agents.size(), 8u);
  EXPECT_TRUE(read.agents[AgentId(0)].collector);
  EXPECT_FALSE(read.agents[AgentId(2)].collector);
  EXPECT_EQ(read.agents[AgentId(2)].segment, SegmentId(1));
  ASSERT_EQ(read.routes.size(), a.routes.size());
  EXPECT_EQ(read.routes[CollectorId(0)].waypoints.size(), a.routes[CollectorId(0)].waypoints.size());
}

TEST_F(PlanTest, BadRequestsAreClearErrors) {
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

TEST_F(PlanTest, OptionsOutsideTheirRangeNameTheField) {
  plan::PlannerOptions opt;
  opt.pair_sources = 0;
  try {
    plan::plan_configuration(*ctx_, partition::Method::kBap, 2, opt);
    FAIL() << "pair_sources = 0 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pair_sources = 0 must be in [1, 64]"), std::string::npos) << e.what();
  }
  opt = plan::PlannerOptions{};
  opt.home_box_margin_m = -1.0;
  EXPECT_THROW(plan::sweep(*ctx_, opt), Error);
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
TEST_F(PlanTest, TheTuningFieldsHaveRangesAndEachChangesThePlan) {
  const struct {
    const char* message;
    void (*set)(plan::PlannerOptions&);
  } bad[] = {
      {"pass_step_m = 0.01 must be in [0.05, 5] m", [](plan::PlannerOptions& o) { o.pass_step_m = 0.01; }},
      {"pass_probe_m = 2 must be in [0.01, 1] m", [](plan::PlannerOptions& o) { o.pass_probe_m = 2.0; }},
      {"tight_speed = 0 must be in (0, 1]", [](plan::PlannerOptions& o) { o.tight_speed = 0.0; }},
      {"contact_step_m = 0 must be in [0.05, 5] m", [](plan::PlannerOptions& o) { o.contact_step_m = 0.0; }},
      {"lateness_bins = 4 must be in [8, 4096]", [](plan::PlannerOptions& o) { o.lateness_bins = 4; }},
      {"delivery_samples = 0 must be in [1, 256]", [](plan::PlannerOptions& o) { o.delivery_samples = 0; }},
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

TEST_F(PlanTest, ThePassRadiusDecidesWhereARoutePassesNextToASegment) {
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
