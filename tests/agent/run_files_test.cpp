// runner/run_files: gather run's CSVs have the simulator's schema, and
// mission.yaml says what the mission did.
#include "gather_agent/runner/run_files.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "corridor_team.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/mission/mission_csv.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;

TEST(RunFiles, WritesTheSimulatorsSchemaAndAMissionFile) {
  CorridorTeam c(2, {{0, Point2{5.05, 0.25}}, {1, Point2{9.05, 0.25}}});
  const RunOutcome out = TeamRunner(*c.team, RunOptions{}).run();
  ASSERT_TRUE(out.completed);
  RunFiles files;
  files.add(c.plan.file, c.team->params, out);
  const std::string dir = ::testing::TempDir() + "/gather_run_files_test";
  files.write(dir);
  auto first_line = [](const std::string& path) {
    std::ifstream in(path);
    std::string l;
    std::getline(in, l);
    return l + "\n";
  };
  EXPECT_EQ(first_line(dir + "/goals.csv"), mission::kGoalsCsvHeader);
  EXPECT_EQ(first_line(dir + "/cycles.csv"), mission::kCyclesCsvHeader);
  EXPECT_EQ(first_line(dir + "/summary.csv"), mission::kSummaryCsvHeader);
  EXPECT_EQ(first_line(dir + "/agents.csv"), kAgentsCsvHeader);
  LoadedPlan lp;
  lp.dir = dir, lp.plan = c.plan, lp.scenario = c.scenario;
  write_mission_yaml(dir + "/mission.yaml", lp, c.team->params, RunSettings{"in-process", 0.1, 0.0, 0.0}, out);
  std::ifstream in(dir + "/mission.yaml");
  const std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(yaml.find("status: ok"), std::string::npos);
  EXPECT_NE(yaml.find("requested: 2, delivered: 2"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("role: collector"), std::string::npos);
}

}  // namespace
}  // namespace agent
}  // namespace gather
