#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

#include <unistd.h>

#include <filesystem>

#include "gather_agent/motion/motion_backend.hpp"
#include "gather_agent/roles/oc_role.hpp"
#include "gather_agent/runner/agent_fleet.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_oc/mission_view.hpp"
#include "gather_oc/plan_markers.hpp"
#include "gather_oc/ros_conversions.hpp"
#include "gather_oc/scan_relay.hpp"

namespace gather {
namespace {

const std::string kScenario = std::string(GATHER_REPO_DIR) + "/../shared/maps/ipa/office_a.scenario.yaml";

// A plan of maps/office (bap, no collectors) in a temp directory, made once.
const std::string& plan_dir() {
  static const std::string dir = [] {
    const std::string d = ::testing::TempDir() + "/gather_oc_test_plan_" + std::to_string(::getpid());
    const Scenario map = load_scenario(std::string(GATHER_REPO_DIR) + "/maps/office.scenario.yaml");
    const Scenario s = on_planning_grid(map, planning_factor(map));
    const plan::PlanContext ctx(s);
    plan::write_plan_directory(d, ctx, plan::plan_configuration(ctx, partition::Method::kBap, 0), 1);
    return d;
  }();
  return dir;
}

TEST(RosConversions, MapMessageKeepsCellsAndGeometry) {
  const Scenario s = load_scenario(kScenario);
  const auto m = to_map_msg(s.grid, "map", ros::Time(5.0));
  EXPECT_EQ(m.header.frame_id, "map");
  EXPECT_EQ(m.info.width, 1194u);
  EXPECT_EQ(m.info.height, 685u);
  EXPECT_FLOAT_EQ(m.info.resolution, 0.05f);
  ASSERT_EQ(m.data.size(), s.grid.size());
  for (std::size_t i = 0; i < m.data.size(); i += 997) EXPECT_EQ(m.data[i], s.grid.values()[i]);
  // nav_msgs cell (0,0) is the lower-left corner, like the grid's.
  const Cell oc = s.grid.world_to_cell(s.oc);
  EXPECT_EQ(m.data[oc.row * m.info.width + oc.col], 0);
}

TEST(RosConversions, AMapMessageBecomesAGridOrANamedError) {
  const Scenario s = load_scenario(kScenario);
  const OccupancyGrid back = from_map_msg(to_map_msg(s.grid, "map", ros::Time(1.0)), "/map");
  EXPECT_EQ(back.width(), s.grid.width());
  EXPECT_EQ(back.values(), s.grid.values());
  EXPECT_EQ(back.free_mask(), s.grid.free_mask());
  EXPECT_EQ(back.resolution(), 0.05);  // the YAML's value, not float32's 0.0500000007
  auto refused = [](nav_msgs::OccupancyGrid m) {
    try {
      from_map_msg(m, "/some_map");
    } catch (const Error& e) {
      return std::string(e.what()).rfind("/some_map: ", 0) == 0;
    }
    return false;
  };
  nav_msgs::OccupancyGrid m = to_map_msg(s.grid, "map", ros::Time(1.0));
  nav_msgs::OccupancyGrid bad = m;
  bad.data.pop_back();
  EXPECT_TRUE(refused(bad));
  bad = m, bad.info.resolution = 0.0f;
  EXPECT_TRUE(refused(bad));
  bad = m, bad.info.width = 0;
  EXPECT_TRUE(refused(bad));
  bad = m, bad.info.origin.orientation.z = 0.38, bad.info.origin.orientation.w = 0.92;
  EXPECT_TRUE(refused(bad));
  bad = m, bad.info.origin.position.x = std::nan("");
  EXPECT_TRUE(refused(bad));
}

// maps/office planned with PAP and 4 collectors, with its world and team.
struct Pap4 {
  agent::LoadedPlan plan;
  std::unique_ptr<mission::World> world;
  std::unique_ptr<agent::TeamSetup> team;
  explicit Pap4(int cycles) {
    static const std::string dir = [] {
      const std::string d = ::testing::TempDir() + "/gather_oc_test_pap4_" + std::to_string(::getpid());
      const Scenario map = load_scenario(std::string(GATHER_REPO_DIR) + "/maps/office.scenario.yaml");
      const Scenario sc = on_planning_grid(map, planning_factor(map));
      const plan::PlanContext ctx(sc);
      plan::write_plan_directory(d, ctx,
                                 plan::plan_configuration(ctx, partition::Method::kPap, 4, plan::grown_groups()), 1);
      return d;
    }();
    plan = agent::load_plan(dir);
    world = std::make_unique<mission::World>(plan.scenario);
    agent::MissionParams params = agent::mission_params(plan.scenario);
    params.cycles = cycles;
    team = std::make_unique<agent::TeamSetup>(*world, plan.plan, params);
  }
};

const visualization_msgs::Marker* find(const visualization_msgs::MarkerArray& a, const std::string& ns, int id) {
  for (const auto& m : a.markers)
    if (m.ns == ns && m.id == id) return &m;
  return nullptr;
}

int count(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  int n = 0;
  for (const auto& m : a.markers) n += m.ns == ns;
  return n;
}

bool same_colour(const std_msgs::ColorRGBA& a, const std_msgs::ColorRGBA& b) {
  return std::abs(a.r - b.r) < 1e-6 && std::abs(a.g - b.g) < 1e-6 && std::abs(a.b - b.b) < 1e-6;
}

TEST(PlanMarkers, SegmentsIdsOcCoverageRoutesAndMeetings) {
  Pap4 p(1);
  const view::Style style(p.plan.scenario.grid);
  const auto a = view::plan_markers(*p.team, style, "map", ros::Time(1.0));
  const int workers = p.plan.plan.file.workers;
  ASSERT_EQ(count(a, "segments"), 1);
  const auto* seg = find(a, "segments", 0);
  EXPECT_EQ(seg->type, visualization_msgs::Marker::TRIANGLE_LIST);
  EXPECT_EQ(seg->points.size() % 6, 0u);
  EXPECT_EQ(seg->colors.size(), seg->points.size());
  // The rectangles cover exactly the labelled cells.
  double area = 0.0;
  for (std::size_t i = 0; i < seg->points.size(); i += 6)
    area += std::abs(seg->points[i + 1].x - seg->points[i].x) * std::abs(seg->points[i + 2].y - seg->points[i].y);
  std::size_t labelled = 0;
  for (int32_t l : p.plan.plan.labels) labelled += l > 0;
  EXPECT_NEAR(area, labelled * p.plan.scenario.grid.cell_area(), 1e-6 * area);
  EXPECT_EQ(count(a, "segment_ids"), workers);
  ASSERT_NE(find(a, "oc", 0), nullptr);
  EXPECT_NEAR(find(a, "oc", 0)->pose.position.x, p.plan.scenario.oc.x, 1e-9);
  const auto* cov = find(a, "coverage", 0);
  ASSERT_NE(cov, nullptr);
  EXPECT_GT(cov->points.size(), 8u);
  EXPECT_EQ(cov->points.size() % 2, 0u);
  ASSERT_EQ(count(a, "routes"), 4);
  for (int c = 0; c < 4; ++c)
    for (int d = 0; d < c; ++d) EXPECT_FALSE(same_colour(find(a, "routes", c)->color, find(a, "routes", d)->color));
  int meetings = 0;
  for (const auto& r : p.plan.plan.file.routes) meetings += static_cast<int>(r.meetings.size());
  EXPECT_GE(count(a, "meetings"), meetings);
  EXPECT_GE(count(a, "legend"), 20);  // ten items, a symbol and a text each
}

TEST(MissionView, AgentsByRoleInTheirCollectorsColoursWithIdsLinksAndFrames) {
  Pap4 p(1);
  const view::Style style(p.plan.scenario.grid);
  view::MissionView v(*p.team, style, "map");
  std::vector<agent::Reply> agents(static_cast<std::size_t>(p.team->agents()));
  for (int a = 0; a < p.team->agents(); ++a) {
    agents[static_cast<std::size_t>(a)].agent = static_cast<int16_t>(a);
    agents[static_cast<std::size_t>(a)].pose = p.team->start_pose(AgentId(a));
  }
  const auto m = v.team_markers(agents, 0.0, true, ros::Time(1.0));
  EXPECT_EQ(count(m, "agents"), p.team->agents());
  EXPECT_EQ(count(m, "agent_ids"), p.team->agents());
  int collectors = 0, oc_workers = 0;
  for (int a = 0; a < p.team->agents(); ++a) {
    const auto& as = p.team->assignment(AgentId(a));
    const auto* mk = find(m, "agents", a);
    ASSERT_NE(mk, nullptr);
    if (as.collector) {
      ++collectors;
      EXPECT_EQ(mk->type, visualization_msgs::Marker::CUBE);
      EXPECT_TRUE(same_colour(mk->color, style.collector(as.delivers_to)));
    } else {
      EXPECT_EQ(mk->type, visualization_msgs::Marker::CYLINDER);
      const std_msgs::ColorRGBA want = !as.delivers_to.valid() ? style.oc_worker : style.collector(as.delivers_to);
      oc_workers += !as.delivers_to.valid();
      EXPECT_TRUE(same_colour(mk->color, want)) << "agent " << a;
    }
  }
  EXPECT_EQ(collectors, 4);
  // All of them next to the OC: in radio contact.
  const auto* links = find(m, "links", 0);
  ASSERT_NE(links, nullptr);
  EXPECT_GT(links->points.size(), 2u * static_cast<std::size_t>(p.team->agents()));
  // A hand-over is drawn for a few seconds, then gone; a goal id outside the
  // ledger (a bad reply) is ignored, not allocated for.
  agent::Station station(p.plan.scenario.oc);
  const agent::OcRole oc(*p.team, station);
  agent::ViewEvents ev;
  ev.handovers.push_back(agent::HandoverEvent{5, 0, 3, 10.0});
  ev.measured.push_back(agent::MeasuredEvent{2000000000, 3, 10.0});
  v.take(ev, oc);
  EXPECT_EQ(v.goal_state(oc, GoalId(0)), 0);
  EXPECT_EQ(find(v.team_markers(agents, 11.0, true, ros::Time(11.0)), "handovers", 0)->points.size(), 2u);
  EXPECT_EQ(find(v.team_markers(agents, 20.0, true, ros::Time(20.0)), "handovers", 0)->action,
            visualization_msgs::Marker::DELETE);
  // TF: map -> agent_k/base_link, heading the way it moved.
  auto tf = v.transforms(agents, ros::Time(1.0));
  agents[7].pose.y += 1.0;
  tf = v.transforms(agents, ros::Time(2.0));
  ASSERT_EQ(tf.transforms.size(), agents.size());
  EXPECT_EQ(tf.transforms[7].header.frame_id, "map");
  EXPECT_EQ(tf.transforms[7].child_frame_id, "agent_7/base_link");
  EXPECT_NEAR(tf.transforms[7].transform.rotation.z, std::sin(M_PI / 4), 1e-9);  // yaw 90 degrees
  const auto states = v.agent_states(agents, oc, ros::Time(2.0));
  EXPECT_EQ(states.agents.size(), agents.size());
  EXPECT_EQ(states.agents[0].role_name, p.team->assignment(AgentId(0)).collector ? "collector" : "worker");
}

TEST(MissionView, GoalsByStateAddUpAndEveryCycleIsReportedOnceResolved) {
  Pap4 p(2);
  const view::Style style(p.plan.scenario.grid);
  view::MissionView v(*p.team, style, "map");
  agent::TeamRunner runner(*p.team, agent::RunOptions{});
  std::vector<gather_msgs::CycleStats> reported;
  bool more = true;
  int steps = 0;
  while (more) {
    more = runner.tick();
    if (++steps % 200 != 0 && more) continue;
    const agent::OcRole& oc = runner.oc();
    const auto s = v.status(oc, "running", runner.now(), 0.0, ros::Time(1.0));
    EXPECT_EQ(s.pending + s.carried + s.delivered + s.expired + s.dropped, s.requested);
    for (const auto& c : v.resolved_cycles(oc, ros::Time(1.0))) reported.push_back(c);
  }
  const agent::OcRole& oc = runner.oc();
  for (const auto& c : v.resolved_cycles(oc, ros::Time(1.0))) reported.push_back(c);
  const auto s = v.status(oc, "done", runner.now(), 0.0, ros::Time(1.0));
  EXPECT_EQ(s.requested, oc.requested());
  EXPECT_EQ(s.pending + s.carried, 0u);
  EXPECT_GT(s.delivered, 0u);
  ASSERT_EQ(reported.size(), 2u);
  const std::vector<mission::CycleStats> truth = mission::account(oc.goals(), 2, p.team->period);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(reported[c].cycle, c);
    EXPECT_EQ(static_cast<int>(reported[c].delivered), truth[c].delivered);
    EXPECT_EQ(static_cast<int>(reported[c].requested), truth[c].requested);
    EXPECT_EQ(static_cast<int>(reported[c].expired), truth[c].expired);
    EXPECT_EQ(static_cast<int>(reported[c].dropped), truth[c].dropped);
    EXPECT_NEAR(reported[c].refresh_mean, truth[c].refresh_mean_s, 1e-9);
    EXPECT_DOUBLE_EQ(reported[c].refresh_max, truth[c].refresh_max_s);
  }
  EXPECT_EQ(s.delivered, static_cast<uint32_t>(truth[0].delivered + truth[1].delivered));
  EXPECT_EQ(reported[1].total_requested, s.requested);
  // The goal markers of the last two requests hold every goal, each once.
  const auto g = v.goal_markers(oc, ros::Time(1.0));
  std::size_t shown = 0;
  for (const auto& m : g.markers) shown += m.points.size();
  EXPECT_EQ(shown, oc.requested());
  EXPECT_EQ(find(g, "goals_pending", 0)->action, visualization_msgs::Marker::DELETE);
}

TEST(ScanRelay, AScanIsALaserScanInItsOwnFrameAndPointsInTheMap) {
  agent::RobotScan s;
  s.agent = 4, s.stamp = 12.5, s.at = Point2{3.0, 2.0}, s.heading = M_PI / 2;
  s.angle_min = -M_PI / 2, s.angle_increment = M_PI / 2, s.range_max = 5.0f, s.rays = 3;
  s.ranges[0] = 1.0f, s.ranges[1] = 2.0f, s.ranges[2] = std::numeric_limits<float>::infinity();
  const ros::Time stamp(12.5);
  const sensor_msgs::LaserScan m = to_laser_scan(s, stamp);
  EXPECT_EQ(m.header.frame_id, "agent_4/laser");
  EXPECT_EQ(m.header.stamp, stamp);
  EXPECT_FLOAT_EQ(m.angle_min, -M_PI / 2);
  EXPECT_FLOAT_EQ(m.angle_max, M_PI / 2);
  EXPECT_FLOAT_EQ(m.range_max, 5.0f);
  ASSERT_EQ(m.ranges.size(), 3u);
  EXPECT_TRUE(std::isinf(m.ranges[2]));
  const geometry_msgs::TransformStamped t = laser_transform(s, "map", stamp);
  EXPECT_EQ(t.header.frame_id, "map");
  EXPECT_EQ(t.child_frame_id, "agent_4/laser");
  EXPECT_DOUBLE_EQ(t.transform.translation.x, 3.0);
  EXPECT_NEAR(t.transform.rotation.z, std::sqrt(0.5), 1e-12);
  // Facing +y: the first ray (right of it) points along +x, the second
  // along +y; the third met nothing and is no point.
  const visualization_msgs::Marker p = laser_points(s, "map", stamp, 0.05, view::rgba(1, 0, 0));
  EXPECT_EQ(p.ns, "laser");
  EXPECT_EQ(p.id, 4);
  ASSERT_EQ(p.points.size(), 2u);
  EXPECT_NEAR(p.points[0].x, 4.0, 1e-6);
  EXPECT_NEAR(p.points[0].y, 2.0, 1e-6);
  EXPECT_NEAR(p.points[1].x, 3.0, 1e-6);
  EXPECT_NEAR(p.points[1].y, 4.0, 1e-6);
}

TEST(AgentFleet, StartsAndStopsRealAgentsCleanly) {
  AgentFleet fleet({GATHER_AGENT_BIN, "--id", "{id}", "--lcm-url", "memq://", "--insecure", "--plan", plan_dir()}, 3);
  fleet.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));  // waiting for an OC that never comes
  EXPECT_TRUE(fleet.poll().empty()) << "an agent ended early";
  fleet.stop(2.0);
  for (const auto& a : fleet.agents()) {
    EXPECT_EQ(a.exit_status, 0) << "agent " << a.id;
    EXPECT_GE(a.stop_latency_s, 0.0);
    EXPECT_LT(a.stop_latency_s, 1.0);
  }
}

TEST(AgentFleet, ReportsAnAgentThatDiesEarly) {
  AgentFleet fleet(
      {GATHER_AGENT_BIN, "--id", "{id}", "--lcm-url", "memq://", "--insecure", "--plan", "/nonexistent/plan"}, 2);
  fleet.start();
  std::vector<int> ended;
  for (int i = 0; i < 200 && ended.size() < 2; ++i) {
    for (int id : fleet.poll()) ended.push_back(id);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(ended.size(), 2u);
  EXPECT_TRUE(fleet.agents()[0].exited_early);
  EXPECT_EQ(fleet.agents()[0].exit_status, 2);
}

TEST(AgentFleet, FindsAnExplicitBinaryOnlyIfExecutable) {
  EXPECT_EQ(find_agent_binary(GATHER_AGENT_BIN), GATHER_AGENT_BIN);
  EXPECT_EQ(find_agent_binary("/nonexistent/gather_agent"), "");
}

}  // namespace
}  // namespace gather
