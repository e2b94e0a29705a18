#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "gather_oc/agent_fleet.hpp"
#include "gather_oc/mission_results.hpp"
#include "gather_oc/ros_conversions.hpp"

namespace gather {
namespace {

const std::string kScenario = std::string(GATHER_REPO_DIR) + "/../shared/maps/ipa/office_a.scenario.yaml";

std::vector<uint8_t> encoded_heartbeat(int id, Role role, Point2 p, int skip = 0) {
  Heartbeat hb(id, role, p);
  for (int i = 0; i < skip; ++i) hb.next(0);
  const auto m = hb.next(0);
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
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

TEST(RosConversions, MarkersShowOcAndHeardAgents) {
  FleetMonitor fleet(3);
  const auto a = encoded_heartbeat(0, Role::kWorker, {1, 2});
  const auto b = encoded_heartbeat(2, Role::kCollector, {3, 4});
  fleet.on_message(a.data(), static_cast<int>(a.size()), 0.0);
  fleet.on_message(b.data(), static_cast<int>(b.size()), 9.0);
  const auto markers = team_markers({5, 6}, fleet.agents(), "map", ros::Time(1.0), 10.0, 2.0);
  int spheres = 0;
  for (const auto& m : markers.markers) {
    if (m.ns == "oc") EXPECT_DOUBLE_EQ(m.pose.position.x, 5.0);
    if (m.ns != "agents") continue;
    ++spheres;
    if (m.id == 0) EXPECT_LT(m.color.a, 1.0f);  // stale: heard 10 s ago
    if (m.id == 2) EXPECT_DOUBLE_EQ(m.pose.position.y, 4.0);
  }
  EXPECT_EQ(spheres, 2);
}

TEST(MissionResults, WritesAReadableFile) {
  const Scenario s = load_scenario(kScenario);
  FleetMonitor fleet(s.team.agents);
  for (int i = 0; i < s.team.agents; ++i) {
    const auto m = encoded_heartbeat(i, Role::kUnassigned, {1, 1});
    fleet.on_message(m.data(), static_cast<int>(m.size()), 0.0);
  }
  const auto late = encoded_heartbeat(4, Role::kUnassigned, {1, 1}, 3);  // seq 3: 2 missed
  fleet.on_message(late.data(), static_cast<int>(late.size()), 0.0);
  const MissionSummary sum = summarize(fleet, 3.0);
  EXPECT_TRUE(sum.ok());
  EXPECT_EQ(sum.missed, 2);
  const std::string path = ::testing::TempDir() + "/gather_oc_test/mission.yaml";
  write_mission_results(path, s, fleet, sum);
  const YAML::Node y = YAML::LoadFile(path);
  EXPECT_EQ(y["status"].as<std::string>(), "ok");
  EXPECT_EQ(y["agents_heard"].as<int>(), 20);
  EXPECT_EQ(y["agents"].size(), 20u);
  EXPECT_EQ(y["agents"][4]["heartbeats"].as<int>(), 2);
  EXPECT_EQ(y["map"]["width"].as<int>(), 1194);
}

TEST(AgentFleet, StartsAndStopsRealAgentsCleanly) {
  AgentFleet fleet({GATHER_AGENT_BIN, "--id", "{id}", "--lcm-url", "memq://", kScenario}, 3);
  fleet.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_TRUE(fleet.poll().empty()) << "an agent ended early";
  fleet.stop(2.0);
  for (const auto& a : fleet.agents()) {
    EXPECT_EQ(a.exit_status, 0) << "agent " << a.id;
    EXPECT_GE(a.stop_latency_s, 0.0);
    EXPECT_LT(a.stop_latency_s, 1.0);
  }
}

TEST(AgentFleet, ReportsAnAgentThatDiesEarly) {
  AgentFleet fleet({GATHER_AGENT_BIN, "--id", "{id}", "--lcm-url", "memq://", "/nonexistent.yaml"}, 2);
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
