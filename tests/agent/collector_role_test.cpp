// roles/collector_role: a collector driven by hand acks and stores once,
// refuses when full, delivers in the coverage and relays requests.
#include "gather_agent/roles/collector_role.hpp"

#include <gtest/gtest.h>

#include "corridor_team.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;
using agent_testing::measured;
using agent_testing::message;
using agent_testing::request;
using agent_testing::Stepper;

TEST(CollectorRole, AcksStoresOnceRefusesWhenFullDeliversInCoverageRelaysRequests) {
  CorridorTeam c(2);
  c.team->params.data_capacity = 2;
  const OccupancyGrid& grid = c.scenario.grid;
  Stepper k{make_agent(*c.team, AgentId(0))};
  k.step(0.0, {request(0, 0, {{19.05, 0.25}}, grid, kOc, kBroadcast)});
  // Its worker's data at t = 5 s (both at x ~ 5.5 m): acked, picked up now.
  Message d = message(Kind::kData, 1, 0, 0, Point2{5.5, 0.25});
  d.data.count = 1, d.data.items[0] = measured(0, 1, 4.5);
  k.step(5.0, {d});
  const Message* ack = k.sent(Kind::kAck);
  ASSERT_NE(ack, nullptr);
  EXPECT_EQ(ack->ack.count, 1u);
  // The same item again (its ack was lost): acked again, stored once.
  k.step(5.1, {d});
  ASSERT_NE(k.sent(Kind::kAck), nullptr);
  EXPECT_EQ(k.unit.role->custody()->data(), 1u);
  EXPECT_EQ(k.unit.role->custody()->item(0).picked_up_by, 0);
  EXPECT_NEAR(k.unit.role->custody()->item(0).picked_up_at, 5.0, 1e-9);
  // Two more: one fits (capacity 2), the other is refused and not acked.
  Message two = message(Kind::kData, 1, 0, 1, Point2{5.7, 0.25});
  two.data.count = 2, two.data.items[0] = measured(1, 1, 5.0), two.data.items[1] = measured(2, 1, 5.1);
  k.step(5.2, {two});
  ASSERT_NE(k.sent(Kind::kAck), nullptr);
  EXPECT_EQ(k.sent(Kind::kAck)->ack.count, 1u);
  EXPECT_EQ(k.unit.role->report().refused_full, 1);
  // The meeting area (arc 14.5 m) at 14.5 s: request 0 goes to the worker.
  bool relayed = false, delivered_early = false;
  double t = 5.3;
  for (; t < 15.0; t += 0.1) {
    k.step(t);
    if (const Message* r = k.sent(Kind::kRequest)) relayed = relayed || (r->h.dest == 1 && std::abs(t - 14.5) < 0.15);
    delivered_early = delivered_early || k.sent(Kind::kData);
  }
  EXPECT_TRUE(relayed);
  EXPECT_FALSE(delivered_early);  // out of the OC's coverage all along
  // Back in the coverage at 26.95 s: its data goes to the OC.
  double delivered = -1;
  for (; t < 30.0 && delivered < 0; t += 0.1) {
    k.step(t);
    if (const Message* m = k.sent(Kind::kData)) {
      delivered = t;
      EXPECT_EQ(m->h.dest, kOc);
    }
  }
  EXPECT_NEAR(delivered, 26.95, 0.15);
}
}  // namespace
}  // namespace agent
}  // namespace gather
