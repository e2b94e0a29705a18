#include <gtest/gtest.h>

#include <vector>

#include "gather_agent/fleet_monitor.hpp"
#include "gather_agent/heartbeat.hpp"

namespace gather {
namespace {

std::vector<uint8_t> encode(const gather_lcm::agent_state_t& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

TEST(Heartbeat, SequenceGrowsByOneAndCarriesPose) {
  Heartbeat hb(3, Role::kWorker, Point2{1.5, -2.0});
  const auto a = hb.next(100);
  const auto b = hb.next(200);
  EXPECT_EQ(a.agent_id, 3);
  EXPECT_EQ(a.seq, 0);
  EXPECT_EQ(b.seq, 1);
  EXPECT_EQ(b.stamp_us, 200);
  EXPECT_EQ(a.role, gather_lcm::agent_state_t::ROLE_WORKER);
  EXPECT_DOUBLE_EQ(a.x, 1.5);
  EXPECT_DOUBLE_EQ(a.y, -2.0);
  EXPECT_EQ(a.schema_version, gather_lcm::agent_state_t::SCHEMA_VERSION);
}

TEST(FleetMonitor, CountsHeartbeatsAndMissedSequenceNumbers) {
  FleetMonitor fleet(2);
  Heartbeat hb(1, Role::kCollector, Point2{4.0, 5.0});
  for (int i = 0; i < 5; ++i) {
    const auto m = hb.next(i);
    if (i == 2) continue;  // lost on the way
    const auto buf = encode(m);
    EXPECT_EQ(fleet.on_message(buf.data(), static_cast<int>(buf.size()), i), FleetMonitor::Verdict::kAccepted);
  }
  EXPECT_EQ(fleet.heard(), 1);
  const AgentRecord& r = fleet.agents()[1];
  EXPECT_EQ(r.heartbeats, 4);
  EXPECT_EQ(r.first_seq, 0);
  EXPECT_EQ(r.last_seq, 4);
  EXPECT_EQ(r.missed, 1);
  EXPECT_EQ(r.role, Role::kCollector);
  EXPECT_DOUBLE_EQ(r.pose.x, 4.0);
  EXPECT_DOUBLE_EQ(r.first_heard_s, 0.0);
  EXPECT_DOUBLE_EQ(r.last_heard_s, 4.0);
  EXPECT_FALSE(fleet.agents()[0].heard);
}

TEST(FleetMonitor, DuplicatesAreNotCountedTwice) {
  FleetMonitor fleet(1);
  Heartbeat hb(0, Role::kWorker, Point2{});
  const auto buf = encode(hb.next(0));
  fleet.on_message(buf.data(), static_cast<int>(buf.size()), 0);
  fleet.on_message(buf.data(), static_cast<int>(buf.size()), 0);
  EXPECT_EQ(fleet.agents()[0].heartbeats, 1);
  EXPECT_EQ(fleet.agents()[0].out_of_order, 1);
}

TEST(FleetMonitor, RejectsWhatDoesNotDecodeOrBelong) {
  FleetMonitor fleet(2);
  Heartbeat hb(5, Role::kWorker, Point2{});
  auto buf = encode(hb.next(0));
  EXPECT_EQ(fleet.on_message(buf.data(), static_cast<int>(buf.size()), 0), FleetMonitor::Verdict::kUnknownAgent);
  EXPECT_EQ(fleet.on_message(buf.data(), static_cast<int>(buf.size()) - 3, 0), FleetMonitor::Verdict::kUndecodable);
  buf[0] ^= 0xff;  // corrupt the type fingerprint
  EXPECT_EQ(fleet.on_message(buf.data(), static_cast<int>(buf.size()), 0), FleetMonitor::Verdict::kUndecodable);
  Heartbeat ok(0, Role::kWorker, Point2{});
  auto m = ok.next(0);
  m.schema_version = 99;
  const auto future = encode(m);
  EXPECT_EQ(fleet.on_message(future.data(), static_cast<int>(future.size()), 0), FleetMonitor::Verdict::kWrongSchema);
  EXPECT_EQ(fleet.rejected(), 4);
  EXPECT_EQ(fleet.heard(), 0);
}

}  // namespace
}  // namespace gather
