// roles/worker_role: a worker driven by hand on the corridor measures, hands
// over in contact, resends a lost ack, reports expiry, and ignores a request
// larger than its mission's.
#include "gather_agent/roles/worker_role.hpp"

#include <gtest/gtest.h>

#include "corridor_team.hpp"
#include "gather_agent/runner/team_runner.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;
using agent_testing::measured;
using agent_testing::message;
using agent_testing::request;
using agent_testing::Stepper;

TEST(WorkerRole, MeasuresHandsOverInContactResendsALostAckAndReportsExpiry) {
  CorridorTeam c(3);
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper w{make_agent(*c.team, AgentId(1))};
  // Request 0 from the OC: goals at x = 5.05 (4.5 m from the OC) and 19.05.
  w.step(0.0, {request(0, 0, {{5.05, 0.25}, {19.05, 0.25}}, grid, kOc, kBroadcast)});
  auto& role = static_cast<WorkerRole&>(*w.unit.role);
  EXPECT_EQ(role.phase(), WorkerRole::Phase::kMoving);
  const Message* data = nullptr;
  double t = 0.0;
  for (; t < 10.0 && !data; t += 0.1) {
    w.step(t);
    data = w.sent(Kind::kData);
  }
  // Measured on arrival (about 4.5 m at 1 m/s from its start next to the OC),
  // in radio contact with the collector driving alongside: sent at once.
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(data->h.dest, 0);
  ASSERT_EQ(data->data.count, 1u);
  EXPECT_EQ(data->data.items[0].key, 0);
  // Measured on arrival: it heard the request at t = 0.1 s and walked from
  // its start pose at 1 m/s.
  const double walk = 5.05 - c.team->start_pose(AgentId(1)).x;
  EXPECT_NEAR(data->data.items[0].at, 0.1 + walk, 0.15);
  const double first = t;
  // No ack: sent again after resend_after (1 s) while in contact.
  double again = -1;
  for (; t < first + 3.0 && again < 0; t += 0.1) {
    w.step(t);
    if (w.sent(Kind::kData)) again = t;
  }
  EXPECT_NEAR(again - first, 1.0, 0.15);
  Message ack = message(Kind::kAck, 0, 1, 1, w.unit.motion->pose());
  ack.ack.count = 1, ack.ack.keys[0] = 0;
  w.step(t, {ack});
  EXPECT_EQ(role.custody()->data(), 0u);
  // The goal at 19.05 cannot be measured before the collector brings request
  // 1 (114.5 s): unless the worker gets there, it expires then, as a notice.
  for (t += 0.1; t < 130.0; t += 0.1) w.step(t);
  const RoleReport r = role.report();
  EXPECT_EQ(r.measured + r.expired, 2);
}

TEST(WorkerRole, IgnoresARequestLargerThanTheMissionsOwn) {
  CorridorTeam c(3);  // goals_per_request 4
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper w{make_agent(*c.team, AgentId(1))};
  std::vector<Point2> five = {{3.05, 0.25}, {4.05, 0.25}, {5.05, 0.25}, {6.05, 0.25}, {7.05, 0.25}};
  w.step(0.0, {request(0, 0, five, grid, kOc, kBroadcast)});
  EXPECT_EQ(static_cast<WorkerRole&>(*w.unit.role).phase(), WorkerRole::Phase::kStart);
  EXPECT_EQ(w.unit.role->newest_request(), -1);
}
}  // namespace
}  // namespace agent
}  // namespace gather
