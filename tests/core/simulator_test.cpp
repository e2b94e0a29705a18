// mission/simulator: the analytic simulator on the corridor by hand and on
// the small office (conservation, determinism, plan directories).
#include <gtest/gtest.h>

#include <unistd.h>
#include <limits>

#include <filesystem>
#include <set>

#include "corridor.hpp"
#include "gather_core/error.hpp"
#include "gather_core/figures/partition_figure.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/radio/radio_model.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

using mission::GoalRecord;
using mission::MissionOptions;
using mission::MissionResult;
using mission::MissionSimulator;
using testing_support::corridor;
using testing_support::corridor_plan;

// Writes a configuration as a plan directory (labels.png + plan.yaml, as
// `gather plan` does) and loads it back as the simulator would.
mission::MissionPlan through_plan_directory(const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg) {
  static int count = 0;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("gather_mission_test_" + std::to_string(::getpid()) + "_" + std::to_string(count++));
  std::filesystem::create_directories(dir);
  partition::write_label_png((dir / "labels.png").string(), cfg.partition);
  plan::write_plan_file((dir / "plan.yaml").string(), plan::make_plan_file(ctx, cfg, "labels.png", 1));
  mission::MissionPlan loaded = mission::load_mission_plan(dir.string());
  std::filesystem::remove_all(dir);
  return loaded;
}

const GoalRecord& goal_at(const MissionResult& r, double x, int cycle) {
  for (const GoalRecord& g : r.goals)
    if (g.cycle == cycle && std::abs(g.point.x - x) < 0.06) return g;
  throw Error("test", "no such goal");
}

// Invariants every run must satisfy, beyond the accounting's own checks.
void check_invariants(const MissionResult& r, int cycles, int collectors) {
  ASSERT_EQ(static_cast<int>(r.cycles.size()), cycles);
  int delivered = 0;
  std::set<GoalId> ids;
  for (const GoalRecord& g : r.goals) {
    EXPECT_TRUE(ids.insert(g.id).second);
    if (g.measured_at >= 0) {
      EXPECT_GE(g.measured_at, g.requested_at - 1e-9);
      EXPECT_LE(g.measured_at, g.deadline + 1e-9);
      EXPECT_EQ(g.measured_by, g.worker);
      EXPECT_EQ(g.state, mission::GoalState::kDelivered) << "data dropped: goal " << g.id;
    } else {
      EXPECT_EQ(g.state, mission::GoalState::kExpired);
      EXPECT_EQ(g.expired_at, g.deadline);
    }
    if (g.picked_up_at >= 0) {
      EXPECT_GE(g.picked_up_at, g.measured_at - 1e-3);
      EXPECT_GE(g.delivered_at, g.picked_up_at);
      EXPECT_EQ(g.delivered_by, g.picked_up_by);
      EXPECT_LT(g.picked_up_by.value(), collectors);  // collector k is agent k
    } else if (g.delivered_at >= 0) {
      EXPECT_GE(g.delivered_at, g.measured_at);
      EXPECT_EQ(g.delivered_by, g.measured_by);
    }
    delivered += g.delivered_at >= 0;
  }
  int per_cycle = 0;
  for (const auto& c : r.cycles) {
    per_cycle += c.delivered;
    EXPECT_EQ(c.delivered + c.expired, c.requested);
    EXPECT_EQ(c.total_requested, c.total_delivered + c.total_carried + c.total_pending + c.total_expired);
    if (c.delivered > 0) {
      EXPECT_LE(c.refresh_mean_s, c.refresh_max_s);
    }
  }
  EXPECT_EQ(per_cycle, delivered);
  EXPECT_NEAR(r.goals_per_cycle * cycles, delivered, 1e-9);
}

TEST(MissionTest, CorridorDeliveryTimesAreExact) {
  const Scenario s = corridor();
  const plan::PlanContext ctx(s);
  MissionSimulator sim(ctx, corridor_plan(s));
  const auto& iv = sim.route(CollectorId(0)).coverage_intervals();
  ASSERT_EQ(iv.size(), 2u);
  EXPECT_NEAR(iv[0].second, 2.05, 1e-5);
  EXPECT_NEAR(iv[1].first, 26.95, 1e-5);
  MissionOptions opt;
  opt.cycles = 2;
  opt.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{17.05, 0.25}}, {1, Point2{19.05, 0.25}}};
  const MissionResult r = sim.run(opt);
  check_invariants(r, 2, 1);
  const double range = RadioModel(s.grid, s.radio).free_space_range();  // 2.07 m
  // A: measured at 4.5 s with the collector driving alongside (they left the
  // OC together at the same speed): taken at once, dropped where the route
  // re-enters the coverage (arc 26.95 m).
  const GoalRecord& a = goal_at(r, 5.05, 0);
  EXPECT_NEAR(a.measured_at, 4.5, 1e-3);
  EXPECT_NEAR(a.picked_up_at, 4.5, 1e-3);
  EXPECT_NEAR(a.delivered_at, 26.95, 1e-3);
  EXPECT_EQ(a.delivered_by, AgentId(0));
  // B lies beyond the pass: measured at 16.5 s (the collector is 4 m away,
  // driving back), back at the pass at 18.5 s; the collector's next loop
  // (t = 29 s) comes within radio range of the pass at 43.5 s - range.
  const GoalRecord& b = goal_at(r, 17.05, 0);
  EXPECT_NEAR(b.measured_at, 16.5, 1e-3);
  EXPECT_NEAR(b.picked_up_at, 43.5 - range, 1e-3);
  EXPECT_NEAR(b.delivered_at, 55.95, 1e-3);
  // The collector drives floor(100 / 29) = 3 loops per request period (t = 0,
  // 29, 58) and waits at the OC from 87 s. Request 1 (t = 100 s) leaves with
  // it and reaches the worker at the meeting area at 114.5 s; C is 4 m away:
  // 118.5 s, back 122.5 s; the loop of 129 s comes within range at
  // 143.5 s - range and drops C at 155.95 s.
  const GoalRecord& c = goal_at(r, 19.05, 1);
  EXPECT_NEAR(c.measured_at, 118.5, 1e-3);
  EXPECT_NEAR(c.picked_up_at, 143.5 - range, 1e-3);
  EXPECT_NEAR(c.delivered_at, 155.95, 1e-3);
  EXPECT_NEAR(r.cycles[0].refresh_mean_s, (26.95 + 55.95) / 2, 1e-3);
  EXPECT_NEAR(r.cycles[0].refresh_max_s, 55.95, 1e-3);
  EXPECT_NEAR(r.cycles[1].refresh_mean_s, 55.95, 1e-3);
  EXPECT_EQ(r.cycles[0].total_carried, 0);
  // Both metrics by hand. Latency: the mean of delivered_at - requested_at
  // over the goals, (26.95 + 55.95 + 55.95) / 3. Interval: the corridor is
  // one area (a 20 m tile); its data reached the OC at 26.95, 55.95 and
  // 155.95 s: gaps 29 and 100 s.
  EXPECT_NEAR(r.refresh_mean_s, (26.95 + 55.95 + 55.95) / 3, 1e-3);
  EXPECT_NEAR(r.interval_mean_s, (29.0 + 100.0) / 2, 1e-3);
  EXPECT_NEAR(r.interval_max_s, (29.0 + 100.0) / 2, 1e-3);
}

TEST(MissionMetricsTest, IntervalPerAreaByHand) {
  // Areas are 10 m tiles: tile 0 (x in [0, 10)) holds 100 m^2 of reachable
  // space, tiles 1 and 2 50 m^2 each, tile 3 20 m^2. Tile 0: deliveries at
  // 10, 10.0004 (the same delivery), 40 and 100 s: gaps 30 and 60, mean 45.
  // Tile 1: one delivery: the whole mission (3 x 50 s). Tile 2: deliveries
  // at 20 and 30 s: 10. Tile 3: none: the whole mission. An undelivered goal
  // does not count, nor a goal outside the areas; two segments in one tile
  // are one area.
  auto goal = [](int segment, double x, double delivered_at) {
    GoalRecord g;
    g.segment = SegmentId(segment), g.point = Point2{x, 1.0}, g.delivered_at = delivered_at;
    return g;
  };
  mission::AreaWeights areas;
  areas.tile = 10.0;
  for (const auto& [x, m2] : {std::pair{5.0, 100.0}, {15.0, 50.0}, {25.0, 50.0}, {35.0, 20.0}})
    areas.area[mission::area_of(Point2{x, 1.0}, 10.0)] = m2;
  const std::vector<GoalRecord> goals{goal(1, 1.0, 10.0),  goal(1, 2.0, 10.0004), goal(2, 9.0, 40.0),
                                      goal(1, 5.0, 100.0), goal(3, 15.0, 70.0),   goal(4, 25.0, 20.0),
                                      goal(4, 26.0, 30.0), goal(4, 27.0, -1.0),   goal(0, 45.0, 5.0)};
  const auto [mean, max] = mission::interval_stats(goals, 3, 50.0, areas);
  EXPECT_NEAR(mean, (100 * 45.0 + 50 * 150.0 + 50 * 10.0 + 20 * 150.0) / 220, 1e-9);
  EXPECT_NEAR(max, 150.0, 1e-9);
  EXPECT_EQ(mission::interval_stats({}, 3, 50.0, mission::AreaWeights{}), std::make_pair(0.0, 0.0));
  EXPECT_EQ(mission::area_of(Point2{-0.5, 3.0}, 10.0), mission::area_of(Point2{-9.5, 9.9}, 10.0));
  EXPECT_NE(mission::area_of(Point2{-0.5, 3.0}, 10.0), mission::area_of(Point2{0.5, 3.0}, 10.0));
}

TEST(MissionTest, WorkerThatMissesItsCollectorDeliversOnTheNextPass) {
  const Scenario s = corridor();
  const plan::PlanContext ctx(s);
  MissionSimulator sim(ctx, corridor_plan(s));
  MissionOptions opt;
  opt.cycles = 1;
  opt.fixed_goals = {{0, Point2{17.05, 0.25}}};  // measured 16.5 s; the first pass was 14.5 s
  const MissionResult r = sim.run(opt);
  check_invariants(r, 1, 1);
  const GoalRecord& g = r.goals.at(0);
  const double range = RadioModel(s.grid, s.radio).free_space_range();
  EXPECT_NEAR(g.picked_up_at, 14.5 + 29.0 - range, 1e-3);  // the next loop, in radio range of the pass
  EXPECT_NEAR(g.delivered_at, 14.5 + 29.0 + 12.45, 1e-3);
}

TEST(MissionTest, RequestsArrivingTogetherLeaveOnlyTheNewest) {
  // T = 10 s, route 29 s: driven back to back (t = 0, 29, 58, ...).
  // Request 1 (t = 10 s) waits for the collector to re-enter the coverage
  // (26.95 s) and reaches the worker at the next pass (43.5 s), together
  // with request 2 (t = 20 s), which supersedes it: its goal expires there
  // unmeasured. Request 0 is known from the start and valid for one period
  // (mission::request_deadline): the goal measured at 4.5 s is delivered,
  // the one 12 m further (16.5 s) expires at 10 s.
  Scenario s = corridor();
  s.mission.period = 10.0;
  const plan::PlanContext ctx(s);
  MissionSimulator sim(ctx, corridor_plan(s));
  MissionOptions opt;
  opt.cycles = 2;
  opt.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{17.05, 0.25}}, {1, Point2{5.05, 0.25}}};
  const MissionResult r = sim.run(opt);
  check_invariants(r, 2, 1);
  EXPECT_EQ(goal_at(r, 5.05, 0).state, mission::GoalState::kDelivered);
  EXPECT_NEAR(goal_at(r, 5.05, 0).measured_at, 4.5, 1e-3);
  EXPECT_EQ(goal_at(r, 17.05, 0).state, mission::GoalState::kExpired);
  EXPECT_NEAR(goal_at(r, 17.05, 0).expired_at, 10.0, 1e-3);
  EXPECT_EQ(goal_at(r, 5.05, 1).state, mission::GoalState::kExpired);
  EXPECT_NEAR(goal_at(r, 5.05, 1).expired_at, 43.5, 1e-3);
}

// The one expiry rule: a worker of the OC gets the same span as the worker
// of a collector above, one request period from when the request reached it.
// The corridor without its collector, T = 10 s: the OC worker knows request
// 0 at t = 0; it measures the goal at 4.5 s, the one 14 m further would
// take it until 18.5 s: it expires at 10 s (before the rule it measured all
// its request whatever the time), and the worker comes back with the first.
// Its deadline for a request learned at t is t + T.
TEST(MissionTest, OneExpiryRuleForWorkersOfTheOcToo) {
  Scenario s = corridor();
  s.mission.period = 10.0;
  const plan::PlanContext ctx(s);
  MissionSimulator sim(ctx, testing_support::corridor_plan_without_collector(s));
  MissionOptions opt;
  opt.cycles = 1;
  opt.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{19.05, 0.25}}};
  const MissionResult r = sim.run(opt);
  check_invariants(r, 1, 1);
  EXPECT_EQ(goal_at(r, 5.05, 0).state, mission::GoalState::kDelivered);
  EXPECT_NEAR(goal_at(r, 5.05, 0).measured_at, 4.5, 1e-3);
  EXPECT_EQ(goal_at(r, 19.05, 0).state, mission::GoalState::kExpired);
  EXPECT_NEAR(goal_at(r, 19.05, 0).expired_at, 10.0, 1e-3);
  EXPECT_NEAR(mission::request_deadline(37.0, std::numeric_limits<double>::infinity(), 10.0), 47.0, 1e-12);
  EXPECT_NEAR(mission::request_deadline(37.0, 41.0, 10.0), 41.0, 1e-12);  // superseded earlier
}

// The simulator executes it: the goal measured at 4.5 s reaches the
// collector 10 s of link later (the worker walks alongside it, so the link
// holds from the measurement on: taken on the way at 14.5 s); instantly
// without a rate. One hand-over carries one goal (capacity 1): the second
// goal is measured only once the first has gone; without a rate, on the
// way out.
TEST(HandoverTest, TheSimulatorHandsOverAfterTheTransferTime) {
  for (const double bitrate : {1000.0, 0.0}) {
    Scenario s = testing_support::lingering_strip();
    s.radio.bitrate_bps = bitrate;
    const plan::PlanContext ctx(s);
    MissionSimulator sim(ctx, testing_support::lingering_plan(s));
    MissionOptions opt;
    opt.cycles = 1;
    opt.fixed_goals = {{0, Point2{5.05, 0.25}}, {0, Point2{7.05, 0.25}}};
    const MissionResult r = sim.run(opt);
    check_invariants(r, 1, 1);
    const GoalRecord& a = goal_at(r, 5.05, 0);
    EXPECT_NEAR(a.measured_at, 4.5, 1e-3);
    EXPECT_NEAR(a.picked_up_at, bitrate > 0 ? 14.5 : 4.5, 1e-3);
    const GoalRecord& b = goal_at(r, 7.05, 0);
    EXPECT_EQ(b.state, mission::GoalState::kDelivered);
    if (bitrate > 0)
      EXPECT_GT(b.measured_at, a.picked_up_at);
    else
      EXPECT_NEAR(b.measured_at, 6.5, 1e-3);
  }
}

class MissionOfficeTest : public testing_support::SmallOfficeTest {};

TEST_F(MissionOfficeTest, ConservationAndNoDuplicatesOverManySeeds) {
  const std::pair<partition::Method, int> configs[] = {
      {partition::Method::kBap, 2}, {partition::Method::kPap, 1}, {partition::Method::kRap, 3}};
  for (const auto& [method, nc] : configs) {
    const auto cfg = plan::plan_configuration(*ctx_, method, nc);
    MissionSimulator sim(*ctx_, mission::mission_plan(*ctx_, cfg));
    for (unsigned seed = 1; seed <= 12; ++seed) {
      MissionOptions opt;
      opt.cycles = 6;
      opt.seed = seed;
      const MissionResult r = sim.run(opt);
      SCOPED_TRACE(std::string(partition::method_name(method)) + " Nc=" + std::to_string(nc) + " seed " +
                   std::to_string(seed));
      check_invariants(r, 6, nc);
      EXPECT_EQ(r.goals.size(), 6u * 20u);
      EXPECT_GT(r.goals_per_cycle, 0.0);
    }
  }
}

TEST_F(MissionOfficeTest, DeterministicForASeed) {
  const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kBap, 2);
  MissionSimulator sim(*ctx_, mission::mission_plan(*ctx_, cfg));
  MissionOptions opt;
  opt.cycles = 4;
  opt.seed = 7;
  const MissionResult a = sim.run(opt), b = sim.run(opt);
  ASSERT_EQ(a.goals.size(), b.goals.size());
  for (std::size_t i = 0; i < a.goals.size(); ++i) {
    EXPECT_EQ(a.goals[i].point.x, b.goals[i].point.x);
    EXPECT_EQ(a.goals[i].delivered_at, b.goals[i].delivered_at);
  }
  opt.seed = 8;
  const MissionResult c = sim.run(opt);
  bool differ = false;
  for (std::size_t i = 0; i < a.goals.size(); ++i) differ |= a.goals[i].point.x != c.goals[i].point.x;
  EXPECT_TRUE(differ);
}

TEST_F(MissionOfficeTest, NoCollectorsEveryWorkerDeliversToTheOc) {
  const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kBap, 0);
  MissionSimulator sim(*ctx_, mission::mission_plan(*ctx_, cfg));
  for (unsigned seed = 1; seed <= 5; ++seed) {
    MissionOptions opt;
    opt.cycles = 5;
    opt.seed = seed;
    const MissionResult r = sim.run(opt);
    check_invariants(r, 5, 0);
    EXPECT_GT(r.goals_per_cycle, 0.0);
    for (const GoalRecord& g : r.goals) {
      EXPECT_LT(g.picked_up_at, 0);
      if (g.delivered_at >= 0) {
        EXPECT_EQ(g.delivered_by, g.measured_by);
      }
    }
  }
}

TEST_F(MissionOfficeTest, PlanDirectoryGivesTheSameMissionAsTheInMemoryPlan) {
  const auto cfg = plan::plan_configuration(*ctx_, partition::Method::kPap, 2);
  const mission::MissionPlan loaded = through_plan_directory(*ctx_, cfg);
  // The PNG holds the labels and the size, not the placement.
  EXPECT_EQ(loaded.labels.values(), cfg.partition.labels.values());
  EXPECT_TRUE(loaded.labels.frame().same_size(ctx_->scenario.grid.frame()));
  EXPECT_EQ(loaded.labels.frame().resolution, 1.0);
  EXPECT_EQ(cfg.partition.labels.frame(), ctx_->scenario.grid.frame());
  MissionOptions opt;
  opt.cycles = 3;
  MissionSimulator a(*ctx_, mission::mission_plan(*ctx_, cfg)), b(*ctx_, loaded);
  const MissionResult ra = a.run(opt), rb = b.run(opt);
  ASSERT_EQ(ra.goals.size(), rb.goals.size());
  for (std::size_t i = 0; i < ra.goals.size(); ++i)
    EXPECT_NEAR(ra.goals[i].delivered_at, rb.goals[i].delivered_at, 1e-3);
}

// The office planned on a 2x coarser grid (as planner.max_cells does for big
// maps): plan.yaml records the factor, and the simulator, given the scenario
// on that grid, runs the stored plan with the invariants holding.
TEST(MissionCoarseGridTest, PlanOnACoarserGridRunsFromItsDirectory) {
  Scenario map = testing_support::small_office();
  map.map_meta.resolution = map.grid.resolution();
  map.planner.max_cells = 20000;  // 57600 cells -> factor 2
  const int factor = planning_factor(map);
  ASSERT_EQ(factor, 2);
  const Scenario s = on_planning_grid(map, factor);
  EXPECT_EQ(s.grid.width(), 180);
  EXPECT_DOUBLE_EQ(s.grid.resolution(), 0.2);
  const plan::PlanContext ctx(s);
  const auto cfg = plan::plan_configuration(ctx, partition::Method::kBap, 2);
  const mission::MissionPlan loaded = through_plan_directory(ctx, cfg);
  EXPECT_EQ(loaded.file.grid_factor, 2);
  // The map's own grid does not fit the stored labels: a clear error.
  const plan::PlanContext fine(map);
  EXPECT_THROW(MissionSimulator(fine, loaded), Error);
  const Scenario again = on_planning_grid(map, loaded.file.grid_factor);
  const plan::PlanContext ctx2(again);
  MissionSimulator sim(ctx2, loaded);
  MissionOptions opt;
  opt.cycles = 4;
  const MissionResult r = sim.run(opt);
  check_invariants(r, 4, 2);
  EXPECT_GT(r.goals_per_cycle, 0.0);
}

}  // namespace
}  // namespace gather
