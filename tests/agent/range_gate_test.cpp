// transport/range_gate: a message is heard only where the radio model links
// sender and receiver (walls included), seeded injected loss, and the inbox
// of a tick in (sender, seq) order.
#include "gather_agent/transport/range_gate.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "corridor_team.hpp"

namespace gather {
namespace agent {
namespace {

using agent_testing::CorridorTeam;
using agent_testing::message;
using gather::testing_support::corridor;
using gather::testing_support::corridor_plan;

TEST(RangeGate, HearsOnlyWhatTheRadioModelLinks) {
  CorridorTeam c;
  const RangeGate gate(*c.team);
  const Message m = message(Kind::kState, 0, kBroadcast, 0, Point2{1.0, 0.25});
  EXPECT_EQ(gate.admit(m.h, 1, Point2{2.5, 0.25}), RangeGate::Verdict::kPass);
  EXPECT_EQ(gate.admit(m.h, 1, Point2{4.0, 0.25}), RangeGate::Verdict::kOutOfRange);  // 3 m: beyond 2.07 m
}

TEST(RangeGate, AWallInBetweenCutsALinkThatWouldHoldInTheOpen) {
  // 1.5 m apart: -45.3 dBm in the open (sensitivity -49.5), -50.3 through
  // one wall (5 dB). The wall at x = 2.0..2.1 m leaves a gap at the bottom row.
  Scenario s = corridor();
  std::vector<int8_t> v(s.grid.values());
  std::vector<uint8_t> f(s.grid.free_mask());
  for (int r = 1; r < 5; ++r)
    v[static_cast<std::size_t>(r) * 200 + 20] = 100, f[static_cast<std::size_t>(r) * 200 + 20] = 0;
  s.grid = OccupancyGrid(200, 5, 0.1, Point2{0, 0}, v, f);
  const mission::World world(s);
  MissionParams prm;
  prm.cycles = 1;
  TeamSetup team(world, corridor_plan(s), prm);
  const RangeGate gate(team);
  const Message through = message(Kind::kState, 0, kBroadcast, 0, Point2{1.3, 0.25});
  EXPECT_EQ(gate.admit(through.h, 1, Point2{2.8, 0.25}), RangeGate::Verdict::kOutOfRange);
  const Message open = message(Kind::kState, 0, kBroadcast, 0, Point2{1.3, 0.05});  // both in the gap's row
  EXPECT_EQ(gate.admit(open.h, 1, Point2{2.8, 0.05}), RangeGate::Verdict::kPass);
}

TEST(RangeGate, InjectedLossIsSeededAndAtTheRequestedRate) {
  CorridorTeam c;
  const RangeGate a(*c.team, 0.3, 7), b(*c.team, 0.3, 7), other(*c.team, 0.3, 8);
  int lost = 0, same = 0, differ = 0;
  for (uint32_t seq = 0; seq < 4000; ++seq) {
    const Message m = message(Kind::kState, 0, kBroadcast, seq, Point2{1.0, 0.25});
    const auto va = a.admit(m.h, 1, Point2{1.5, 0.25});
    lost += va == RangeGate::Verdict::kLost;
    same += va == b.admit(m.h, 1, Point2{1.5, 0.25});
    differ += va != other.admit(m.h, 1, Point2{1.5, 0.25});
  }
  EXPECT_NEAR(lost / 4000.0, 0.3, 0.03);
  EXPECT_EQ(same, 4000);  // same seed: same losses, whatever the order
  EXPECT_GT(differ, 500);
}

TEST(Inbox, AddressedInRangeInSenderSeqOrderOwnSkippedOverflowCounted) {
  CorridorTeam c;
  const RangeGate gate(*c.team);
  std::vector<Message> sent = {
      message(Kind::kState, 0, kBroadcast, 3, {1, 0.25}), message(Kind::kAck, kOc, 1, 9, {0.55, 0.25}),
      message(Kind::kState, 0, kBroadcast, 2, {1, 0.25}), message(Kind::kAck, kOc, 0, 8, {0.55, 0.25}),  // for agent 0
      message(Kind::kState, 1, kBroadcast, 4, {1, 0.25}),                                                // its own
      message(Kind::kState, 0, kBroadcast, 1, {9, 0.25}),                                                // out of range
  };
  LinkCounters link;
  std::vector<const Message*> inbox;
  inbox.reserve(8);
  gather_inbox(sent, 1, Point2{1.2, 0.25}, gate, link, inbox);
  ASSERT_EQ(inbox.size(), 3u);
  EXPECT_EQ(inbox[0]->h.sender, kOc);
  EXPECT_EQ(inbox[1]->h.seq, 2u);
  EXPECT_EQ(inbox[2]->h.seq, 3u);
  EXPECT_EQ(link.received, 3);
  EXPECT_EQ(link.gated, 1);
  std::vector<const Message*> small;
  small.reserve(1);
  LinkCounters l2;
  gather_inbox(sent, 1, Point2{1.2, 0.25}, gate, l2, small);
  EXPECT_EQ(small.size(), 1u);
  EXPECT_EQ(l2.overflow, 2);
}
}  // namespace
}  // namespace agent
}  // namespace gather
