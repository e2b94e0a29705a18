// plan/association: every worker delivers to one collector or to the OC,
// routes fit the request period, and a move is kept only when it raises the
// score J.
#include "gather_core/plan/association.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "corridor.hpp"
#include "gather_core/plan/planner.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

class AssociationTest : public testing_support::SmallOfficeTest {};

TEST_F(AssociationTest, EveryWorkerIsAssociatedExactlyOnce) {
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

TEST_F(AssociationTest, NoRouteIsLongerThanTheRequestPeriodAndTheDecisionNeverLowersTheScore) {
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

TEST_F(AssociationTest, NoCollectorsSendsEveryWorkerToTheOc) {
  const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kBap, 0);
  EXPECT_TRUE(cfg.routes.empty());
  for (CollectorId c : cfg.collector_of_segment) EXPECT_FALSE(c.valid());
  for (const auto& w : cfg.estimates.workers) EXPECT_FALSE(w.collector.valid());
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

TEST(AssociationCorridorTest, AFarSegmentCheaperFromTheOcGoesToTheOc) {
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

// A 60 m corridor served by one collector at 0.25 m/s with a request every
// 200 s: a route within the period reaches 25 m from the OC at most, so the
// segments whose entry lies farther go to the OC, whichever way the balance
// goes; with drop_out_of_reach they go at once and fewer moves are scored.
TEST(AssociationCorridorTest, SegmentsNoRouteWithinThePeriodReachesGoToTheOcAtOnce) {
  Scenario s = corridor60(RefreshMetric::kInterval);
  s.team.agents = 6, s.team.speed = 0.25;
  s.planner.collectors_max = 1;
  const plan::PlanContext ctx(s);
  const double reach = s.team.speed * ctx.cycle_period / 2.0;
  plan::PlannerOptions off;
  off.drop_out_of_reach = false;
  const auto one_by_one = plan::plan_configuration(ctx, partition::Method::kBap, 1, off);
  const auto at_once = plan::plan_configuration(ctx, partition::Method::kBap, 1);
  int out_of_reach = 0;
  for (SegmentId k : segment_ids(at_once.workers)) {
    if (distance(s.oc, s.grid.cell_center(at_once.graph.segment(k).entry)) <= reach) continue;
    ++out_of_reach;
    EXPECT_FALSE(at_once.collector_of_segment[k].valid()) << k;
    EXPECT_FALSE(one_by_one.collector_of_segment[k].valid()) << k;
  }
  EXPECT_GE(out_of_reach, 2) << "the corridor has no segment out of reach: nothing was tested";
  for (const auto* cfg : {&one_by_one, &at_once})
    for (const auto& r : cfg->routes) EXPECT_LE(r.period, ctx.cycle_period * (1 + 1e-9));
  EXPECT_LT(at_once.moves_scored, one_by_one.moves_scored);
}

// Scoring a whole collector's group as one move only ever adds moves that
// raise the score: on every configuration of the small office with 1-3
// collectors the score with it is at least the score without.
TEST_F(AssociationTest, MovingAWholeGroupNeverLowersTheScore) {
  plan::PlannerOptions single;
  single.idle_whole_groups = false;
  const plan::PlanContext* ctx = ctx_;
  for (partition::Method m : partition::all_methods())
    for (int nc = 1; nc <= 3; ++nc) {
      const auto with = plan::plan_configuration(*ctx, m, nc);
      const auto without = plan::plan_configuration(*ctx, m, nc, single);
      EXPECT_GE(plan::association_score(*ctx, with.estimates), plan::association_score(*ctx, without.estimates) - 1e-12)
          << partition::method_name(m) << " " << nc;
      EXPECT_GE(with.moves_scored, without.moves_scored) << partition::method_name(m) << " " << nc;
    }
}

// The balance scores its trials only once one of them brings the route
// within the period: with 16 robots on the office and a request every
// 80 s, the grown groups make routes so long that balance steps shed
// segments unscored,
// and every route ends within the period; with a request every 600 s every
// trial fits, and none is unscored.
TEST_F(AssociationTest, TheBalanceScoresItsTrialsOnceOneOfThemFitsThePeriod) {
  Scenario crowded = *scenario_;
  crowded.team.agents = 16;
  crowded.mission.period = 80.0;
  const plan::PlanContext ctx(crowded);
  crowded.mission.period = 600.0;
  const plan::PlanContext slow_ctx(crowded);
  int unscored = 0;
  for (partition::Method m : partition::all_methods())
    for (int nc = 1; nc <= 2; ++nc) {
      const auto cfg = plan::plan_configuration(ctx, m, nc);
      unscored += cfg.moves_unscored;
      EXPECT_LE(cfg.moves_unscored, cfg.moved_to_oc);
      for (const auto& r : cfg.routes) EXPECT_LE(r.period, ctx.cycle_period * (1 + 1e-9));
      EXPECT_EQ(plan::plan_configuration(slow_ctx, m, nc).moves_unscored, 0) << partition::method_name(m) << " " << nc;
    }
  EXPECT_GT(unscored, 0) << "no balance step had every trial route over the period: nothing was tested";
}

}  // namespace
}  // namespace gather
