#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include <unistd.h>

#include <filesystem>

#include "gather_agent/runner/agent_fleet.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_oc/ros_conversions.hpp"

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

TEST(RosConversions, MarkersShowTheOcAndEveryAgentByRole) {
  std::vector<agent::Reply> agents(3);
  for (int i = 0; i < 3; ++i) agents[static_cast<std::size_t>(i)].agent = static_cast<int16_t>(i);
  agents[0].role = agent::RoleKind::kWorker, agents[0].pose = {1, 2};
  agents[2].role = agent::RoleKind::kCollector, agents[2].pose = {3, 4};
  const auto markers = team_markers({5, 6}, agents, "map", ros::Time(1.0), true);
  int spheres = 0, labels = 0;
  for (const auto& m : markers.markers) {
    if (m.ns == "oc") EXPECT_DOUBLE_EQ(m.pose.position.x, 5.0);
    if (m.ns == "agent_ids") ++labels;
    if (m.ns != "agents") continue;
    ++spheres;
    if (m.id == 2) {
      EXPECT_DOUBLE_EQ(m.pose.position.y, 4.0);
      EXPECT_LT(m.color.r, 0.2f);  // collectors black
    }
    if (m.id == 0) EXPECT_GT(m.color.b, 0.8f);  // workers blue
  }
  EXPECT_EQ(spheres, 3);
  EXPECT_EQ(labels, 3);
}

TEST(AgentFleet, StartsAndStopsRealAgentsCleanly) {
  AgentFleet fleet({GATHER_AGENT_BIN, "--id", "{id}", "--lcm-url", "memq://", "--plan", plan_dir()}, 3);
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
  AgentFleet fleet({GATHER_AGENT_BIN, "--id", "{id}", "--lcm-url", "memq://", "--plan", "/nonexistent/plan"}, 2);
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
