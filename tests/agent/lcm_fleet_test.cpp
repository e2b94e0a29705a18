// The fleet's LCM edge: every message type survives a round trip through
// LCM (memq://: inside this process, no network) unchanged, and whatever
// does not decode, carries another schema version, names an agent outside
// the team, or holds values out of range is counted and dropped, never
// trusted and never a crash (a mutation fuzz of valid encodings included).
#include <gtest/gtest.h>

#include <cstdlib>

#include <gather_lcm/ack_t.hpp>
#include <gather_lcm/agent_state_t.hpp>
#include <gather_lcm/data_t.hpp>
#include <gather_lcm/fleet_envelope_t.hpp>
#include <gather_lcm/plan_t.hpp>
#include <gather_lcm/request_t.hpp>
#include <gather_lcm/tick_reply_t.hpp>
#include <gather_lcm/tick_t.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <random>

#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_core/input_ranges.hpp"

namespace gather {
namespace agent {
namespace {

template <typename T>
std::vector<uint8_t> encoded(const T& msg) {
  std::vector<uint8_t> b(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

// A fleet key for the tests (not secret).
FleetKey test_key(int16_t id = 7, uint8_t fill = 0x5a) {
  FleetKey k;
  k.id = id;
  k.key.fill(fill);
  return k;
}

// A payload as it travels: in an unsigned envelope from `sender` (what an
// insecure fleet reads; the payload's own checks are what these tests are
// about).
std::vector<uint8_t> in_envelope(const std::vector<uint8_t>& payload, int16_t sender) {
  static int64_t counter = 0;
  gather_lcm::fleet_envelope_t e{};
  e.version = gather_lcm::fleet_envelope_t::VERSION;
  e.key_id = gather_lcm::fleet_envelope_t::UNSIGNED;
  e.sender = sender;
  e.counter = ++counter;
  e.size = static_cast<int32_t>(payload.size());
  e.payload = payload;
  return encoded(e);
}

bool clock_channel(const char* channel) {
  return std::strcmp(channel, kTickChannel) == 0 || std::strcmp(channel, kPlanChannel) == 0 ||
         std::strcmp(channel, kReplyChannel) == 0;
}

// Hands `payload` (in an envelope from `sender`) to the fleet's handler.
void feed(LcmFleet& f, const char* channel, const std::vector<uint8_t>& payload, int16_t sender) {
  const std::vector<uint8_t> b = in_envelope(payload, sender);
  if (clock_channel(channel))
    f.on_clock(channel, b.data(), static_cast<int>(b.size()));
  else
    f.on_radio(channel, b.data(), static_cast<int>(b.size()));
}

Message base(Kind k, int16_t sender, int16_t dest) {
  Message m;
  m.h.kind = k, m.h.sender = sender, m.h.dest = dest, m.h.seq = 7, m.h.tick = 42, m.h.t = 4.2;
  m.h.pos = Point2{1.25, -3.5}, m.h.request = 3;
  return m;
}

Message roundtrip(LcmFleet& f, const Message& m) {
  f.radio().clear();
  EXPECT_TRUE(f.publish(m));
  for (int i = 0; i < 50 && f.radio().empty(); ++i) f.handle(20);
  EXPECT_EQ(f.radio().size(), 1u);
  return f.radio().empty() ? Message{} : f.radio()[0];
}

void expect_header(const Header& a, const Header& b) {
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.sender, b.sender);
  EXPECT_EQ(a.dest, b.dest);
  EXPECT_EQ(a.seq, b.seq);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.pos.x, b.pos.x);
  EXPECT_EQ(a.pos.y, b.pos.y);
  EXPECT_EQ(a.request, b.request);
}

TEST(LcmFleet, EveryRadioMessageSurvivesTheRoundTrip) {
  LcmFleet f("memq://", "memq://", true, test_key(), 20);
  Message r = base(Kind::kRequest, kOc, kBroadcast);
  r.request.request = 3, r.request.issued_at = 300.5, r.request.first_goal = 120, r.request.total = 300;
  r.request.part = 1, r.request.parts = 2, r.request.count = 44;
  for (int i = 0; i < 44; ++i) r.request.cells[i] = static_cast<uint32_t>(1000 + 7 * i);
  r.request.dead_count = 2, r.request.dead[0] = 7, r.request.dead[1] = 3, r.request.dead_revoked = 2;
  Message got = roundtrip(f, r);
  expect_header(got.h, r.h);
  EXPECT_EQ(got.request.dead_count, 2u);
  EXPECT_EQ(got.request.dead[1], 3);
  EXPECT_EQ(got.request.dead_revoked, 2u);
  EXPECT_EQ(got.request.first_goal, 120);
  EXPECT_EQ(got.request.count, 44u);
  EXPECT_EQ(got.request.cells[43], 1000u + 7 * 43);
  EXPECT_EQ(got.request.part, 1u);

  Message d = base(Kind::kData, 5, 0);
  d.data.count = 3;
  d.data.items[0] = DataItem{17, ItemKind::kMeasured, 5, 12.25, 0, 13.5};
  d.data.items[1] = DataItem{18, ItemKind::kExpired, 5, 99.0, -1, -1.0};
  d.data.items[2] = DataItem{skipped_key(4, 5), ItemKind::kSkipped, 5, 400.0, -1, -1.0};
  got = roundtrip(f, d);
  expect_header(got.h, d.h);
  ASSERT_EQ(got.data.count, 3u);
  EXPECT_EQ(got.data.items[0].picked_up_at, 13.5);
  EXPECT_EQ(got.data.items[1].kind, ItemKind::kExpired);
  EXPECT_EQ(skipped_request(got.data.items[2].key), 4);
  EXPECT_EQ(skipped_worker(got.data.items[2].key), 5);

  Message a = base(Kind::kAck, 0, 5);
  a.ack.count = 2, a.ack.keys[0] = 17, a.ack.keys[1] = -9;
  got = roundtrip(f, a);
  EXPECT_EQ(got.ack.count, 2u);
  EXPECT_EQ(got.ack.keys[1], -9);

  Message s = base(Kind::kState, 5, kBroadcast);
  s.state.role = RoleKind::kWorker, s.state.carried = 3, s.state.notices = 1, s.state.pending = 2,
  s.state.measured = 44;
  got = roundtrip(f, s);
  EXPECT_EQ(got.state.measured, 44);
  EXPECT_EQ(got.state.pending, 2u);
  EXPECT_EQ(f.dropped(), 0);
}

TEST(LcmFleet, ClockAndPlanSurviveTheRoundTrip) {
  LcmFleet f("memq://", "memq://", true, test_key(), 20);
  PlanAnnounce p;
  p.digest = 0xfedcba9876543210ull, p.agents = 20, p.params.cycles = 7, p.params.seed = 9,
  p.params.goals_per_request = 40;
  p.params.data_capacity = 160, p.params.notice_capacity = 160, p.tick = 0.05, p.loss = 0.25, p.loss_seed = 3;
  p.params.ask_after = 1.5, p.params.protocol.link_step_m = 0.25, p.params.protocol.window_margin_m = 2.5,
  p.params.protocol.two_opt_rounds = 7;
  f.publish(p);
  PlanAnnounce bad = p;  // a link step out of [0.01, 1] m: refused
  bad.params.protocol.link_step_m = 5.0;
  f.publish(bad);
  PlanAnnounce bad_margin = p;  // a window margin out of [0, 100] m: refused
  bad_margin.params.protocol.window_margin_m = -1.0;
  f.publish(bad_margin);
  Tick tick;
  tick.tick = 12, tick.t = 1.2, tick.sent_before = 33, tick.commands_before = 4, tick.report = true;
  tick.expect.assign(20, 0);
  tick.expect[4] = 33, tick.expect[7] = 2;
  f.publish(tick);
  Reply r;
  r.tick = 12, r.agent = 4, r.sent = 2, r.pose = {3.5, 4.5}, r.role = RoleKind::kCollector, r.keys = {1, 2, 3};
  r.dests = {kBroadcast, 9};
  r.report.measured = 9, r.link.gated = 77;
  r.measured_goals = {41, 42}, r.path_revision = 3, r.path = {{1.0, 2.0}, {3.25, 4.5}, {6.0, 7.0}};
  f.publish(r);
  for (int i = 0; i < 50 && (f.plans().empty() || f.ticks().empty() || f.replies().empty()); ++i) f.handle(20);
  ASSERT_EQ(f.plans().size(), 1u);
  EXPECT_EQ(f.plans()[0].digest, p.digest);
  EXPECT_EQ(f.plans()[0].params.cycles, 7);
  EXPECT_EQ(f.plans()[0].loss, 0.25);
  EXPECT_EQ(f.plans()[0].params.ask_after, 1.5);
  EXPECT_EQ(f.plans()[0].params.protocol.link_step_m, 0.25);
  EXPECT_EQ(f.plans()[0].params.protocol.window_margin_m, 2.5);
  EXPECT_EQ(f.plans()[0].params.protocol.two_opt_rounds, 7);
  ASSERT_EQ(f.ticks().size(), 1u);
  EXPECT_EQ(f.ticks()[0].sent_before, 33);
  EXPECT_EQ(f.ticks()[0].commands_before, 4);
  EXPECT_TRUE(f.ticks()[0].report);
  EXPECT_EQ(f.ticks()[0].expect, tick.expect);
  ASSERT_EQ(f.replies().size(), 1u);
  EXPECT_EQ(f.replies()[0].keys.size(), 3u);
  EXPECT_EQ(f.replies()[0].dests, r.dests);
  EXPECT_EQ(f.replies()[0].link.gated, 77);
  EXPECT_EQ(f.replies()[0].role, RoleKind::kCollector);
  EXPECT_EQ(f.replies()[0].measured_goals, (std::vector<int32_t>{41, 42}));
  EXPECT_EQ(f.replies()[0].path_revision, 3u);
  ASSERT_EQ(f.replies()[0].path.size(), 3u);
  EXPECT_DOUBLE_EQ(f.replies()[0].path[1].x, 3.25);
  EXPECT_DOUBLE_EQ(f.replies()[0].path[1].y, 4.5);
}

TEST(LcmFleet, AReplyWithoutKeysCarriesNoneOfThePreviousReplysKeys) {
  // The generated decoder reuses its arrays (and resizes them only for a
  // non-zero count): a reply with no keys after one with keys once came out
  // with the earlier keys, and the conservation check saw goals twice.
  LcmFleet f("memq://", "memq://", true, std::nullopt, 20);
  Reply a;
  a.tick = 1, a.agent = 1, a.keys = {7, 8, 9}, a.measured_goals = {7}, a.path_revision = 1, a.path = {{1, 1}, {2, 2}};
  Reply b;
  b.tick = 1, b.agent = 2, b.path_revision = 1;
  f.publish(a);
  f.publish(b);
  for (int i = 0; i < 50 && f.replies().size() < 2; ++i) f.handle(20);
  ASSERT_EQ(f.replies().size(), 2u);
  EXPECT_EQ(f.replies()[0].keys.size(), 3u);
  EXPECT_TRUE(f.replies()[1].keys.empty());
  EXPECT_TRUE(f.replies()[1].measured_goals.empty());
  EXPECT_TRUE(f.replies()[1].path.empty());
}

TEST(LcmFleet, RepliesWithTooManyPointsOrNonFinitePathsAreCountedAndDropped) {
  LcmFleet f("memq://", "memq://", true, std::nullopt, 20);
  gather_lcm::tick_reply_t r{};
  r.schema_version = gather_lcm::tick_reply_t::SCHEMA_VERSION;
  r.agent = 2, r.status = 3;
  auto send = [&](const gather_lcm::tick_reply_t& e) { feed(f, kReplyChannel, encoded(e), e.agent); };
  gather_lcm::tick_reply_t ok = r;
  ok.n_path = 2, ok.path_x = {1.0f, 2.0f}, ok.path_y = {1.0f, 2.0f};
  send(ok);
  EXPECT_EQ(f.replies().size(), 1u);
  gather_lcm::tick_reply_t many = r;
  many.n_path = gather_lcm::tick_reply_t::MAX_PATH + 1;
  many.path_x.assign(static_cast<std::size_t>(many.n_path), 0.0f);
  many.path_y.assign(static_cast<std::size_t>(many.n_path), 0.0f);
  send(many);
  gather_lcm::tick_reply_t nan = ok;
  nan.path_y[1] = std::nanf("");
  send(nan);
  gather_lcm::tick_reply_t measured = r;
  measured.n_measured = gather_lcm::tick_reply_t::MAX_MEASURED + 1;
  measured.measured_goals.assign(static_cast<std::size_t>(measured.n_measured), 1);
  send(measured);
  EXPECT_EQ(f.refused().out_of_range, 3);
  EXPECT_EQ(f.replies().size(), 1u);
}

TEST(LcmFleet, GarbageTruncatedOversizedWrongVersionOutOfRangeAreCountedAndDropped) {
  LcmFleet f("memq://", "memq://", true, std::nullopt, 20);
  std::vector<uint8_t> junk(100, 0xab);
  f.on_radio(kDataChannel, junk.data(), static_cast<int>(junk.size()));
  EXPECT_EQ(f.refused().undecodable, 1);

  gather_lcm::data_t d{};
  d.h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  d.h.sender = 3, d.h.dest = kOc;
  d.count = 1;
  d.items[0].kind = 1, d.items[0].by = 3, d.items[0].picked_up_by = -1;
  const std::vector<uint8_t> buf = encoded(d);
  feed(f, kDataChannel, buf, 3);
  ASSERT_EQ(f.radio().size(), 1u);                                             // the valid one
  feed(f, kDataChannel, std::vector<uint8_t>(buf.begin(), buf.end() - 5), 3);  // truncated
  std::vector<uint8_t> longer(buf);
  longer.resize(buf.size() + 4096, 0);  // oversized: trailing bytes
  feed(f, kDataChannel, longer, 3);
  EXPECT_EQ(f.refused().undecodable, 3);

  auto variant = [&](auto edit) {
    gather_lcm::data_t e = d;
    edit(e);
    feed(f, kDataChannel, encoded(e), e.h.sender);
  };
  variant([](gather_lcm::data_t& e) { e.h.schema_version = 1; });
  EXPECT_EQ(f.refused().wrong_version, 1);
  variant([](gather_lcm::data_t& e) { e.h.sender = 20; });  // outside a team of 20
  variant([](gather_lcm::data_t& e) { e.h.dest = 99; });
  variant([](gather_lcm::data_t& e) { e.count = 65; });
  variant([](gather_lcm::data_t& e) { e.count = -1; });
  variant([](gather_lcm::data_t& e) { e.h.x = std::nan(""); });
  variant([](gather_lcm::data_t& e) { e.items[0].kind = 9; });
  variant([](gather_lcm::data_t& e) { e.items[0].at = INFINITY; });
  variant([](gather_lcm::data_t& e) { e.items[0].by = -4; });
  EXPECT_EQ(f.refused().out_of_range, 8);
  EXPECT_EQ(f.radio().size(), 1u);  // still only the valid one

  // A request that says a declaration it does not list was revoked.
  gather_lcm::request_t q{};
  q.h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  q.h.sender = kOc, q.h.dest = kBroadcast;
  q.parts = 1, q.n_dead = 2, q.dead = {4, 6}, q.dead_revoked = 2;
  feed(f, kRequestChannel, encoded(q), kOc);
  ASSERT_EQ(f.radio().size(), 2u);
  EXPECT_EQ(f.radio().back().request.dead_revoked, 2u);
  q.dead_revoked = 4;  // bit 2: no third declaration
  feed(f, kRequestChannel, encoded(q), kOc);
  EXPECT_EQ(f.refused().out_of_range, 9);
  EXPECT_EQ(f.radio().size(), 2u);
}

TEST(LcmFleet, MutatedMessagesNeverCrashAndAreEitherValidOrCounted) {
  LcmFleet f("memq://", "memq://", true, std::nullopt, 20);
  gather_lcm::request_t r{};
  r.h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  r.h.sender = kOc, r.h.dest = kBroadcast, r.parts = 1, r.count = 40;
  std::vector<uint8_t> valid(static_cast<std::size_t>(r.getEncodedSize()));
  r.encode(valid.data(), 0, static_cast<int>(valid.size()));
  std::mt19937_64 rng(11);
  int64_t accepted = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    std::vector<uint8_t> b = valid;
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int k = 0; k < flips; ++k) b[rng() % b.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    if (rng() % 4 == 0) b.resize(rng() % b.size());
    const char* channel = (rng() % 2) ? kRequestChannel : kStateChannel;
    feed(f, channel, b, kOc);
    accepted += static_cast<int64_t>(f.radio().size());
    for (const Message& m : f.radio()) {
      EXPECT_GE(m.h.sender, kOc);
      EXPECT_LT(m.h.sender, 20);
      EXPECT_TRUE(std::isfinite(m.h.t));
      if (m.h.kind == Kind::kRequest) {
        EXPECT_LE(m.request.count, kRequestPartGoals);
      }
    }
    f.radio().clear();
  }
  EXPECT_EQ(accepted + f.dropped(), n);
  EXPECT_GT(f.dropped(), n / 2);
}

// Every channel's type (the fuzz smoke of the LCM payloads: under the
// sanitized build of make test-plain any out-of-bounds read or undefined
// conversion aborts): valid encodings, mutated by bit flips, boundary bytes,
// truncation and trailing garbage, are either accepted (within bounds) or
// counted as refused, one or the other for every message.

TEST(LcmFleet, MutatedPayloadsOfEveryChannelAreAcceptedWithinBoundsOrCounted) {
  LcmFleet f("memq://", "memq://", true, std::nullopt, 20);
  gather_lcm::header_t h{};
  h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  h.sender = 3, h.dest = kOc;
  gather_lcm::data_t d{};
  d.h = h, d.count = 2;
  for (int i = 0; i < 2; ++i)
    d.items[i].kind = 1, d.items[i].by = 3, d.items[i].picked_up_by = -1, d.items[i].key = 7 + i;
  gather_lcm::ack_t a{};
  a.h = h, a.h.sender = kOc, a.h.dest = 3, a.count = 3;
  gather_lcm::agent_state_t st{};
  st.h = h, st.role = gather_lcm::agent_state_t::ROLE_WORKER;
  gather_lcm::request_t rq{};
  rq.h = h, rq.h.sender = kOc, rq.h.dest = kBroadcast, rq.parts = 1, rq.count = 5, rq.total = 5;
  gather_lcm::tick_t tk{};
  tk.schema_version = gather_lcm::tick_t::SCHEMA_VERSION, tk.tick = 5, tk.t = 0.5;
  gather_lcm::plan_t pl{};
  pl.schema_version = gather_lcm::plan_t::SCHEMA_VERSION, pl.agents = 4, pl.cycles = 2, pl.goals_per_request = 8;
  pl.data_capacity = 64, pl.notice_capacity = 64, pl.beacon_period = 1, pl.resend_after = 1, pl.tick = 0.1, pl.rate = 1;
  pl.silent_intervals = 2, pl.ask_after = 0.5, pl.link_step_m = 0.1, pl.window_margin_m = 1.0, pl.two_opt_rounds = 100;
  gather_lcm::tick_reply_t rp{};
  rp.schema_version = gather_lcm::tick_reply_t::SCHEMA_VERSION, rp.agent = 3, rp.status = 1;
  const std::vector<std::pair<const char*, std::vector<uint8_t>>> bases{
      {kDataChannel, encoded(d)},     {kAckChannel, encoded(a)},   {kStateChannel, encoded(st)},
      {kRequestChannel, encoded(rq)}, {kTickChannel, encoded(tk)}, {kPlanChannel, encoded(pl)},
      {kReplyChannel, encoded(rp)}};
  std::mt19937_64 rng(17);
  int64_t accepted = 0;
  const int n = 30000;
  for (int i = 0; i < n; ++i) {
    const auto& [channel, valid] = bases[rng() % bases.size()];
    std::vector<uint8_t> b = valid;
    switch (rng() % 4) {
      case 0:
        for (int k = 0, flips = 1 + static_cast<int>(rng() % 8); k < flips; ++k)
          b[rng() % b.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
        break;
      case 1:
        for (int k = 0, edits = 1 + static_cast<int>(rng() % 4); k < edits; ++k)
          b[rng() % b.size()] = static_cast<uint8_t>(std::array<uint8_t, 4>{0x00, 0xff, 0x7f, 0x80}[rng() % 4]);
        break;
      case 2: b.resize(rng() % b.size()); break;
      default: b.resize(b.size() + 1 + rng() % 64, static_cast<uint8_t>(rng())); break;
    }
    const int64_t before = f.dropped();
    feed(f, channel, b,
         clock_channel(channel) ? (channel == kReplyChannel ? 3 : kOc)
                                : (channel == kAckChannel || channel == kRequestChannel ? kOc : 3));
    const int64_t got =
        static_cast<int64_t>(f.radio().size() + f.ticks().size() + f.plans().size() + f.replies().size());
    EXPECT_EQ(got + f.dropped() - before, 1) << channel << " case " << i;
    accepted += got;
    for (const Message& m : f.radio()) {
      EXPECT_GE(m.h.sender, kOc);
      EXPECT_LT(m.h.sender, 20);
      EXPECT_TRUE(std::isfinite(m.h.t) && std::isfinite(m.h.pos.x) && std::isfinite(m.h.pos.y));
      if (m.h.kind == Kind::kData) {
        EXPECT_LE(m.data.count, kMaxBatch);
      }
      if (m.h.kind == Kind::kAck) {
        EXPECT_LE(m.ack.count, kMaxBatch);
      }
    }
    for (const PlanAnnounce& p : f.plans()) {
      EXPECT_LE(p.params.goals_per_request, input_range(range::kGoalsPerRequest).hi);
      EXPECT_LE(p.params.data_capacity, std::size_t{1} << 22);
      EXPECT_NO_THROW(mission::check_params(p.params.protocol));
    }
    f.radio().clear(), f.ticks().clear(), f.plans().clear(), f.replies().clear();
  }
  EXPECT_EQ(accepted + f.dropped(), n);
  EXPECT_GT(f.dropped(), n / 2);
}

TEST(LcmFleet, TheRepliesUrlIsTheRadiosPortPlusOne) {
  EXPECT_EQ(LcmFleet::reply_url_for("udpm://239.255.76.67:7667?ttl=0"), "udpm://239.255.76.67:7668?ttl=0");
  EXPECT_EQ(LcmFleet::reply_url_for("udpm://239.1.2.3:9000"), "udpm://239.1.2.3:9001");
  EXPECT_EQ(LcmFleet::reply_url_for("udpm://239.1.2.3"), "udpm://239.1.2.3:7668");
  EXPECT_EQ(LcmFleet::reply_url_for("memq://"), "memq://");
}

// An agent that heard nothing from the OC says why it may be: messages that
// failed their check (another key), messages it could not read (another
// version), ttl=0 (nothing leaves the computer), or else the OC or the route.
TEST(LcmFleet, AnAgentThatHearsNothingSaysTheLikelyCause) {
  const AuthCounters none;
  const TransportCounters clean;
  AuthCounters bad_mac;
  bad_mac.bad_mac = 3;
  TransportCounters old;
  old.wrong_version = 2;
  const std::string host = kHostFleetUrl, robots = kRobotFleetUrl;
  EXPECT_NE(silence_cause(robots, bad_mac, clean).find("dropped 3 fleet messages"), std::string::npos);
  EXPECT_NE(silence_cause(robots, bad_mac, clean).find("fleet key"), std::string::npos);
  EXPECT_NE(silence_cause(robots, none, old).find("could not read 2"), std::string::npos);
  EXPECT_NE(silence_cause(host, none, clean).find("ttl=0 keeps LCM multicast on this computer"), std::string::npos);
  EXPECT_NE(silence_cause(host, none, clean).find(robots), std::string::npos);  // what to use instead
  EXPECT_NE(silence_cause(robots, none, clean).find("does multicast reach this computer"), std::string::npos);
  EXPECT_EQ(silence_cause("memq://", none, clean), "is the OC running on this URL?");
  // The URL: the one given, else LCM_DEFAULT_URL, else the fallback.
  EXPECT_EQ(effective_url("memq://", kRobotFleetUrl), "memq://");
  if (!std::getenv("LCM_DEFAULT_URL")) {
    EXPECT_EQ(effective_url("", kRobotFleetUrl), robots);
    EXPECT_EQ(effective_url(""), host);
  }
}

}  // namespace
}  // namespace agent
}  // namespace gather
