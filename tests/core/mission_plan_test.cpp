// mission/mission_plan: check_plan refuses, with one message naming the
// plan and the agent or route at fault, every structure that executing a
// plan relies on and a plan file could get wrong; collector_agents names
// who drives each collector.
#include "gather_core/mission/mission_plan.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "corridor.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace {

using testing_support::corridor;
using testing_support::corridor_plan;

// check_plan's message for `plan` on the corridor's team and grid, "" when
// it accepts it.
std::string refusal(const mission::MissionPlan& plan, const Scenario& s) {
  try {
    mission::check_plan(plan, s.team.agents, s.grid);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CheckPlanTest, TheCorridorPlanIsAcceptedAndItsCollectorIsAgentZero) {
  const Scenario s = corridor();
  mission::MissionPlan plan = corridor_plan(s);
  plan.source = "corridor/plan.yaml";
  EXPECT_EQ(refusal(plan, s), "");
  const PerCollector<AgentId> drivers = mission::collector_agents(plan.file);
  ASSERT_EQ(drivers.count(), 1);
  EXPECT_EQ(drivers[CollectorId(0)], AgentId(0));
}

TEST(CheckPlanTest, EachBrokenStructureIsRefusedNamingThePlanAndTheCulprit) {
  const Scenario s = corridor();
  const struct {
    const char* what;  // a part of the expected message
    std::function<void(mission::MissionPlan&)> breaks;
  } cases[] = {
      {"plans 3 agents, the scenario's team has 2",
       [](mission::MissionPlan& p) {
         p.file.agents.push_back(plan::AgentAssignment{AgentId(2), false, SegmentId(1), CollectorId()});
       }},
      {"agent 5: ids must be 0..1, once each",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(1)].id = AgentId(5); }},
      {"agent 0: ids must be 0..1, once each",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(1)].id = AgentId(0); }},
      {"agent 1: agents must be listed by id (it is entry 0)",
       [](mission::MissionPlan& p) { std::swap(p.file.agents[AgentId(0)], p.file.agents[AgentId(1)]); }},
      {"agent 0: agents 0..0 must be the collectors",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(0)].collector = false; }},
      {"agent 0: a collector's index must be its own id",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(0)].delivers_to = CollectorId(); }},
      {"agent 1: segment must be 1..1, one worker each",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(1)].segment = SegmentId(2); }},
      {"agent 1: collector must be -1 (the OC) or 0..0",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(1)].delivers_to = CollectorId(1); }},
      {"agent 1: collector must be -1 (the OC) or 0..0",
       [](mission::MissionPlan& p) { p.file.agents[AgentId(1)].delivers_to = CollectorId(-2); }},
      {"collector 0 has no meeting area for segment 1 (agent 1)",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].meetings.clear(); }},
      {"route of collector 0: its collector index must be 0",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].collector = CollectorId(3); }},
      {"route of collector 0: a waypoint is not finite or outside the map",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].waypoints[1].x = 500.0; }},
      {"route of collector 0: a waypoint is not finite or outside the map",
       [](mission::MissionPlan& p) {
         p.file.routes[CollectorId(0)].waypoints[1].y = std::numeric_limits<double>::quiet_NaN();
       }},
      {"route of collector 0: length_m is not finite or not the route's",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].length = 1e9; }},
      {"route of collector 0: a coverage entry is not finite or off the route",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].coverage_entries.push_back(-1.0); }},
      {"route of collector 0: a pass is not finite or off the route",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].meetings[0].passes.push_back(100.0); }},
      {"route of collector 0: segment 4 does not exist",
       [](mission::MissionPlan& p) { p.file.routes[CollectorId(0)].segments.push_back(SegmentId(4)); }},
      {"2 routes for 1 collectors",
       [](mission::MissionPlan& p) { p.file.routes.push_back(p.file.routes[CollectorId(0)]); }},
      {"collectors (1) + workers (0) must be the 2 agents", [](mission::MissionPlan& p) { p.file.workers = 0; }},
      {"cycle_period_s = 0 must be in (0, 100000] s", [](mission::MissionPlan& p) { p.file.cycle_period_s = 0; }},
      {"cycle_period_s = 200000 must be in (0, 100000] s",
       [](mission::MissionPlan& p) { p.file.cycle_period_s = 2e5; }},
      {"area_tile_m = -1 must be in (0, 1000000] m", [](mission::MissionPlan& p) { p.file.area_tile_m = -1; }},
      {"area_tile_m = 0.05 must be in [0.1, 1000000] m (at least a cell of the planning grid)",
       [](mission::MissionPlan& p) { p.file.area_tile_m = 0.05; }},
      {"label image is 10x5, the scenario's planning grid 200x5",
       [](mission::MissionPlan& p) {
         p.labels = LabelImage(GridFrame{10, 5}, 1);
       }},
  };
  for (const auto& c : cases) {
    mission::MissionPlan plan = corridor_plan(s);
    plan.source = "corridor/plan.yaml";
    c.breaks(plan);
    const std::string message = refusal(plan, s);
    EXPECT_NE(message.find("corridor/plan.yaml"), std::string::npos) << c.what << ": " << message;
    EXPECT_NE(message.find(c.what), std::string::npos) << "expected '" << c.what << "', got '" << message << "'";
  }
}

TEST(CheckPlanTest, APlanBuiltInMemoryIsNamedPlan) {
  const Scenario s = corridor();
  mission::MissionPlan plan = corridor_plan(s);
  plan.file.cycle_period_s = -5;
  EXPECT_EQ(refusal(plan, s).rfind("plan: ", 0), 0u) << refusal(plan, s);
}

}  // namespace
}  // namespace gather
