// plan/plan_file: plan.yaml written by make_plan_file reads back to the
// same file, and the same seed plans the same file.
#include "gather_core/plan/plan_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/planner.hpp"
#include "small_office.hpp"

namespace gather {
namespace {

class PlanFileTest : public testing_support::SmallOfficeTest {};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST_F(PlanFileTest, SameSeedSamePlanAndFileRoundTrip) {
  const auto a = plan::plan_configuration(*ctx_, partition::Method::kRap, 2);
  const auto b = plan::plan_configuration(*ctx_, partition::Method::kRap, 2);
  EXPECT_EQ(a.partition.labels, b.partition.labels);
  const std::string dir = ::testing::TempDir() + "/gather_plan_file_test";
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

}  // namespace
}  // namespace gather
