// The fleet's time (transport/fleet_clock.hpp, docs/robots.md "Clocks"): an
// agent on a host whose clock is seconds off measures its offset to the OC
// with NTP's four timestamps, keeps the exchange with the shortest round
// trip, and then signs and checks the fleet's traffic on the OC's time;
// before that it takes nothing but the OC's answers, and counts nothing.
#include <gtest/gtest.h>
#include <lcm/lcm.h>

#include <chrono>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/fleet_clock.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"

namespace gather {
namespace agent {
namespace {

constexpr int64_t kSecond = 1'000'000;

FleetKey test_key() {
  FleetKey k;
  k.id = 9;
  k.key.fill(0x33);
  return k;
}

TEST(FleetClock, TheOffsetOfTheShortestRoundTripWins) {
  FleetClock oc;  // the reference
  EXPECT_TRUE(oc.synced());
  EXPECT_EQ(oc.offset_us(), 0);
  FleetClock agent(false);
  EXPECT_FALSE(agent.synced());
  // The agent's clock reads 5 s ahead of the OC's; ways of 2 ms each way.
  const int64_t t = 1'700'000'000 * kSecond, skew = 5 * kSecond;
  ASSERT_TRUE(agent.add(t + skew, t + 2000, t + 2100, t + skew + 4100));
  EXPECT_TRUE(agent.synced());
  EXPECT_EQ(agent.offset_us(), -skew);
  EXPECT_EQ(agent.round_trip_us(), 4000);
  // Queues delay one way by up to 300 ms: the offset stays that of the
  // fastest exchange of the last 8, whatever came after it.
  std::mt19937 rng(1);
  std::uniform_int_distribution<int64_t> queue(0, 300'000);
  struct Kept {
    int64_t offset, round_trip;
  };
  std::vector<Kept> all{{-skew, 4000}};
  auto exchange = [&](int i) {
    const int64_t t0 = t + i * kSecond, out = 2000 + queue(rng), back = 2000 + queue(rng);
    all.push_back({(out - back) / 2 - skew, out + back});
    return agent.add(t0 + skew, t0 + out, t0 + out + 100, t0 + out + 100 + back + skew);
  };
  for (int i = 1; i <= 7; ++i) ASSERT_TRUE(exchange(i));
  EXPECT_EQ(agent.offset_us(), -skew);
  EXPECT_EQ(agent.exchanges(), 8);
  // Eight exchanges later the fast one is out of the window: the offset is
  // that of the shortest round trip among the last eight.
  for (int i = 8; i < 16; ++i) {
    ASSERT_TRUE(exchange(i));
    Kept best = all[all.size() - 8];
    for (std::size_t k = all.size() - 8; k < all.size(); ++k)
      if (all[k].round_trip < best.round_trip) best = all[k];
    EXPECT_NEAR(static_cast<double>(agent.offset_us()), static_cast<double>(best.offset), 1.0) << i;
    EXPECT_EQ(agent.round_trip_us(), best.round_trip) << i;
  }
  EXPECT_NE(agent.offset_us(), -skew);
  EXPECT_EQ(agent.steps(), 0);
  // Exchanges that cannot be (a negative round trip, an answer before the
  // ask was received) or say too little (over a second) are ignored.
  const int64_t kept = agent.offset_us();
  EXPECT_FALSE(agent.add(t + skew, t + 2000, t + 2100, t + skew + 50));
  EXPECT_FALSE(agent.add(t + skew, t + 2000, t + 1000, t + skew + 4000));
  EXPECT_FALSE(agent.add(t + skew, t + 2000, t + 2100, t + skew + 2 * kSecond));
  EXPECT_EQ(agent.offset_us(), kept);
}

// The host's clock steps by 2 s (NTP setting it after boot): the first
// exchange after the step cannot be explained by the kept offset, so the
// samples start afresh; nothing of the old offset survives.
TEST(FleetClock, AClockThatStepsStartsTheSamplesAfresh) {
  FleetClock agent(false);
  const int64_t t = 1'700'000'000 * kSecond;
  for (int i = 0; i < 8; ++i) {
    const int64_t t0 = t + i * kSecond;
    ASSERT_TRUE(agent.add(t0 + 5 * kSecond, t0 + 1000, t0 + 1100, t0 + 5 * kSecond + 2100));  // 2 ms round trip
  }
  EXPECT_EQ(agent.offset_us(), -5 * kSecond);
  const int64_t t0 = t + 10 * kSecond;  // now 7 s ahead, and a slower exchange
  ASSERT_TRUE(agent.add(t0 + 7 * kSecond, t0 + 20'000, t0 + 20'100, t0 + 7 * kSecond + 40'100));
  EXPECT_EQ(agent.offset_us(), -7 * kSecond);
  EXPECT_EQ(agent.steps(), 1);
}

// A sender on the fleet's time, and a receiver whose clock is 5 s behind:
// before it knows its offset it refuses the sender's first message as a
// capture (out of its freshness window), after it accepts it; the clock
// exchange's own channels skip the window.
TEST(FleetClock, SigningFreshnessReadsTheCorrectedClock) {
  const std::vector<std::string> channels{"A", "T"};
  FleetAuth tx(test_key(), channels, 22);
  FleetClock behind(false, -5 * kSecond);
  FleetAuth rx(test_key(), channels, 22, &behind);
  rx.mac_only("T");
  const std::vector<uint8_t> payload{1, 2, 3};
  auto signed_on = [&](const char* channel) {
    EnvelopeHead h;
    std::vector<uint8_t> mac(kMacBytes);
    tx.sign(channel, 3, payload.data(), payload.size(), h, mac.data());
    return std::make_pair(h, mac);
  };
  auto [h1, mac1] = signed_on("A");
  EXPECT_EQ(rx.verify("A", h1, payload.data(), payload.size(), mac1.data()), Verdict::kReplayed);
  auto [ht, mact] = signed_on("T");
  EXPECT_EQ(rx.verify("T", ht, payload.data(), payload.size(), mact.data()), Verdict::kAccepted);
  const int64_t now = behind.local_us();
  ASSERT_TRUE(behind.add(now, now + 5 * kSecond + 1000, now + 5 * kSecond + 1100, now + 2100));
  EXPECT_NEAR(static_cast<double>(behind.offset_us()), 5e6, 2e3);
  auto [h2, mac2] = signed_on("A");
  EXPECT_EQ(rx.verify("A", h2, payload.data(), payload.size(), mac2.data()), Verdict::kAccepted);
  // And what it signs now is stamped on the fleet's time, within the
  // window of a receiver on the OC's clock.
  FleetAuth rx_oc(test_key(), channels, 22);
  FleetAuth tx_behind(test_key(), channels, 22, &behind);
  EnvelopeHead h3;
  std::vector<uint8_t> mac3(kMacBytes);
  tx_behind.sign("A", 4, payload.data(), payload.size(), h3, mac3.data());
  EXPECT_EQ(rx_oc.verify("A", h3, payload.data(), payload.size(), mac3.data()), Verdict::kAccepted);
}

// What an LCM instance carries on one channel, as the bytes on the wire.
struct Tap {
  std::vector<std::vector<uint8_t>> got;
  static void on(const lcm_recv_buf_t* rbuf, const char*, void* user) {
    const auto* b = static_cast<const uint8_t*>(rbuf->data);
    static_cast<Tap*>(user)->got.emplace_back(b, b + rbuf->data_size);
  }
  void drain(lcm_t* lcm) {
    while (lcm_handle_timeout(lcm, 0) > 0) {
    }
  }
};

// The exchange through both sides' handlers, signed, on memq:// (each side
// its own instance: the test carries the bytes across, as the network
// would): an agent whose clock is 5 s ahead ignores the OC's clock ticks
// until it knows its offset, counting nothing, then takes them.
TEST(FleetClock, AnAgentFiveSecondsAheadMeasuresItsOffsetThenTakesTheOcsTicks) {
  LcmFleet oc("memq://", "memq://", true, test_key(), 20);
  LcmFleet agent("memq://", "memq://", false, test_key());
  agent.time_from_oc(3, 5 * kSecond);
  Tap asks, answers, ticks;
  lcm_subscribe(agent.reply_lcm(), kTimeAskChannel, Tap::on, &asks);
  lcm_subscribe(oc.radio_lcm(), kTimeChannel, Tap::on, &answers);
  lcm_subscribe(oc.radio_lcm(), kTickChannel, Tap::on, &ticks);
  Tick p;
  p.tick = 42, p.t = 4.2;
  ASSERT_TRUE(oc.publish(p));
  ticks.drain(oc.radio_lcm());
  ASSERT_EQ(ticks.got.size(), 1u);
  agent.on_clock(kTickChannel, ticks.got[0].data(), static_cast<int>(ticks.got[0].size()));
  EXPECT_TRUE(agent.ticks().empty());
  EXPECT_EQ(agent.dropped(), 0);  // not a capture: its clock is not known yet
  std::vector<uint8_t> stale;
  for (int round = 0; round < 4; ++round) {
    asks.got.clear(), answers.got.clear();
    agent.keep_time();
    asks.drain(agent.reply_lcm());
    ASSERT_EQ(asks.got.size(), 1u) << "round " << round;
    agent.keep_time();  // its ask is out: no second one yet
    asks.drain(agent.reply_lcm());
    EXPECT_EQ(asks.got.size(), 1u);
    oc.on_clock(kTimeAskChannel, asks.got[0].data(), static_cast<int>(asks.got[0].size()));
    answers.drain(oc.radio_lcm());
    ASSERT_EQ(answers.got.size(), 1u);
    agent.on_clock(kTimeChannel, answers.got[0].data(), static_cast<int>(answers.got[0].size()));
    // The same answer again is never a second sample (its t0 was used).
    agent.on_clock(kTimeChannel, answers.got[0].data(), static_cast<int>(answers.got[0].size()));
    EXPECT_EQ(agent.clock().exchanges(), round + 1);
    if (round == 0) {
      // A replayed ask earns an answer that echoes a stale t0: no sample.
      answers.got.clear();
      oc.on_clock(kTimeAskChannel, asks.got[0].data(), static_cast<int>(asks.got[0].size()));
      answers.drain(oc.radio_lcm());
      ASSERT_EQ(answers.got.size(), 1u);
      stale = answers.got[0];
      agent.on_clock(kTimeChannel, stale.data(), static_cast<int>(stale.size()));
      EXPECT_EQ(agent.clock().exchanges(), 1);
      // Another agent's ask and its answer: not this agent's either.
      LcmFleet other("memq://", "memq://", false, test_key());
      other.time_from_oc(4, 0);
      Tap other_asks;
      lcm_subscribe(other.reply_lcm(), kTimeAskChannel, Tap::on, &other_asks);
      other.keep_time();
      other_asks.drain(other.reply_lcm());
      ASSERT_EQ(other_asks.got.size(), 1u);
      answers.got.clear();
      oc.on_clock(kTimeAskChannel, other_asks.got[0].data(), static_cast<int>(other_asks.got[0].size()));
      answers.drain(oc.radio_lcm());
      ASSERT_EQ(answers.got.size(), 1u);
      agent.on_clock(kTimeChannel, answers.got[0].data(), static_cast<int>(answers.got[0].size()));
      EXPECT_EQ(agent.clock().exchanges(), 1);
    } else {  // the stale answer, again, while a new ask is out: still no sample
      agent.on_clock(kTimeChannel, stale.data(), static_cast<int>(stale.size()));
      EXPECT_EQ(agent.clock().exchanges(), round + 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(260));  // the next ask is due
  }
  EXPECT_TRUE(agent.clock().synced());
  EXPECT_NEAR(static_cast<double>(agent.clock().offset_us()), -5e6, 5e4);
  EXPECT_LT(agent.clock().round_trip_us(), 50'000);
  // The OC's next tick: now taken.
  ticks.got.clear();
  ASSERT_TRUE(oc.publish(p));
  ticks.drain(oc.radio_lcm());
  ASSERT_EQ(ticks.got.size(), 1u);
  agent.on_clock(kTickChannel, ticks.got[0].data(), static_cast<int>(ticks.got[0].size()));
  ASSERT_EQ(agent.ticks().size(), 1u);
  EXPECT_EQ(agent.ticks()[0].tick, 42);
  EXPECT_EQ(agent.rejected().total(), 0);  // replays of the exchange are harmless, not refused
  EXPECT_EQ(oc.rejected().total(), 0);
}

// An agent under another key than the OC's: before it knows the fleet's
// time it takes nothing, but it counts what fails its key, so that its last
// line can say "does it hold the OC's fleet key?".
TEST(FleetClock, BeforeItsFirstExchangeAnAgentStillCountsTrafficUnderAnotherKey) {
  LcmFleet oc("memq://", "memq://", true, test_key(), 20);
  FleetKey other = test_key();
  other.key.fill(0x44);
  LcmFleet agent("memq://", "memq://", false, other);
  agent.time_from_oc(3, 0);
  Tap ticks;
  lcm_subscribe(oc.radio_lcm(), kTickChannel, Tap::on, &ticks);
  Tick p;
  p.tick = 1;
  ASSERT_TRUE(oc.publish(p));
  ticks.drain(oc.radio_lcm());
  ASSERT_EQ(ticks.got.size(), 1u);
  agent.on_clock(kTickChannel, ticks.got[0].data(), static_cast<int>(ticks.got[0].size()));
  EXPECT_TRUE(agent.ticks().empty());
  EXPECT_EQ(agent.rejected().bad_mac, 1);
  EXPECT_NE(silence_cause(kRobotFleetUrl, agent.rejected(), agent.refused()).find("fleet key"), std::string::npos);
}

}  // namespace
}  // namespace agent
}  // namespace gather
