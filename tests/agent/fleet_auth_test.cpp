// Signed fleet traffic (docs/security.md): a message signed with the fleet
// key passes; a forged, changed, replayed, unsigned or re-addressed one is
// dropped before it is decoded, and counted by its reason. Key files: made
// with mode 0600, refused when others can read them, malformed ones named.
#include <gtest/gtest.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gather_lcm/ack_t.hpp>
#include <gather_lcm/agent_state_t.hpp>
#include <gather_lcm/data_t.hpp>
#include <gather_lcm/envelope_t.hpp>
#include <gather_lcm/fleet_envelope_t.hpp>
#include <gather_lcm/request_t.hpp>
#include <gather_lcm/tick_t.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/fleet_links.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

const std::vector<std::string> kChannels{"A", "B"};

FleetKey key_of(int16_t id, uint8_t fill) {
  FleetKey k;
  k.id = id;
  k.key.fill(fill);
  return k;
}

struct Signed {
  EnvelopeHead head;
  std::vector<uint8_t> payload;
  uint8_t mac[kMacBytes];
};

Signed sign(FleetAuth& a, const char* channel, int16_t sender, std::vector<uint8_t> payload) {
  Signed s;
  s.payload = std::move(payload);
  a.sign(channel, sender, s.payload.data(), s.payload.size(), s.head, s.mac);
  return s;
}

Verdict check(FleetAuth& a, const char* channel, const Signed& s) {
  return a.verify(channel, s.head, s.payload.data(), s.payload.size(), s.mac);
}

TEST(FleetAuthTest, AGoodMessagePassesOnceAndEveryChangeIsCaughtByItsReason) {
  FleetAuth tx(key_of(7, 1), kChannels, 22), rx(key_of(7, 1), kChannels, 22);
  const Signed good = sign(tx, "A", 3, {1, 2, 3, 4});
  EXPECT_EQ(check(rx, "A", good), Verdict::kAccepted);
  EXPECT_EQ(check(rx, "A", good), Verdict::kReplayed);  // the same message again
  EXPECT_EQ(rx.counters().replayed, 1);

  const Signed next = sign(tx, "A", 3, {5});
  EXPECT_GT(next.head.counter, good.head.counter);
  Signed flipped = next;
  flipped.payload[0] ^= 0x10;
  EXPECT_EQ(check(rx, "A", flipped), Verdict::kBadMac);
  Signed other_sender = next;
  other_sender.head.sender = 4;  // another agent's id on agent 3's message
  EXPECT_EQ(check(rx, "A", other_sender), Verdict::kBadMac);
  Signed later = next;
  later.head.counter += 1000000;  // a counter pushed forward to get past the replay check
  EXPECT_EQ(check(rx, "A", later), Verdict::kBadMac);
  EXPECT_EQ(check(rx, "B", next), Verdict::kBadMac);  // moved to another channel
  EXPECT_EQ(rx.counters().bad_mac, 4);
  EXPECT_EQ(check(rx, "A", next), Verdict::kAccepted);  // untouched, it still passes

  FleetAuth forger(key_of(7, 2), kChannels, 22);  // the right id, a wrong key
  EXPECT_EQ(check(rx, "A", sign(forger, "A", 3, {9})), Verdict::kBadMac);
  FleetAuth other_fleet(key_of(8, 1), kChannels, 22);
  EXPECT_EQ(check(rx, "A", sign(other_fleet, "A", 3, {9})), Verdict::kUnknownKey);
  FleetAuth insecure(std::nullopt, kChannels, 22);
  const Signed plain = sign(insecure, "A", 3, {9});
  EXPECT_EQ(plain.head.key_id, 0);
  EXPECT_EQ(check(rx, "A", plain), Verdict::kUnsigned);
  EXPECT_EQ(rx.counters().bad_mac, 5);
  EXPECT_EQ(rx.counters().unknown_key, 1);
  EXPECT_EQ(rx.counters().unsigned_msgs, 1);
  EXPECT_EQ(rx.counters().total(), 8);
  // An insecure receiver checks nothing.
  EXPECT_EQ(check(insecure, "A", flipped), Verdict::kAccepted);
}

TEST(FleetAuthTest, CountersArePerSenderAndChannelAndSurviveARestart) {
  FleetAuth rx(key_of(7, 1), kChannels, 22);
  {
    // Signed on B, then on A; heard on A, then on B: both pass only because
    // each channel keeps its own counter.
    FleetAuth tx(key_of(7, 1), kChannels, 22);
    const Signed on_b = sign(tx, "B", 5, {1});
    const Signed on_a = sign(tx, "A", 5, {1});
    EXPECT_EQ(check(rx, "A", on_a), Verdict::kAccepted);
    EXPECT_EQ(check(rx, "B", on_b), Verdict::kAccepted);
    // Likewise per sender: agent 6's older message after agent 5's newer one.
    const Signed six = sign(tx, "A", 6, {1});
    const Signed five = sign(tx, "A", 5, {2});
    EXPECT_EQ(check(rx, "A", five), Verdict::kAccepted);
    EXPECT_EQ(check(rx, "A", six), Verdict::kAccepted);
  }
  {
    FleetAuth tx(key_of(7, 1), kChannels, 22);
    for (int i = 0; i < 100; ++i) ASSERT_EQ(check(rx, "A", sign(tx, "A", 3, {1})), Verdict::kAccepted);
    ASSERT_EQ(check(rx, "B", sign(tx, "B", 3, {1})), Verdict::kAccepted);
    ASSERT_EQ(check(rx, "A", sign(tx, "A", -1, {1})), Verdict::kAccepted);  // the OC
  }
  ::usleep(2000);
  // The process restarts with no state: its wall-clock counter is above
  // everything it sent before.
  FleetAuth again(key_of(7, 1), kChannels, 22);
  EXPECT_EQ(check(rx, "A", sign(again, "A", 3, {1})), Verdict::kAccepted);
  EXPECT_EQ(rx.counters().total(), 0);
}

// The MAC by hand, as docs/security.md specifies it: HMAC-SHA-512-256 over
// the channel and its NUL, version, key id, sender, counter and payload size
// (big endian), then the payload.
void mac_by_hand(const FleetKey& k, const char* channel, const EnvelopeHead& h, const std::vector<uint8_t>& payload,
                 uint8_t* out) {
  std::vector<uint8_t> m(channel, channel + std::strlen(channel) + 1);
  auto be = [&](uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) m.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  be(static_cast<uint16_t>(h.version), 2), be(static_cast<uint16_t>(h.key_id), 2),
      be(static_cast<uint16_t>(h.sender), 2);
  be(static_cast<uint64_t>(h.counter), 8), be(payload.size(), 4);
  m.insert(m.end(), payload.begin(), payload.end());
  crypto_auth_hmacsha512256(out, m.data(), m.size(), k.key.data());
}

TEST(FleetAuthTest, TheMacIsTheDocumentedHmacAndAFreshReceiverRefusesOldOrFutureCounters) {
  const FleetKey k = key_of(7, 1);
  FleetAuth tx(k, kChannels, 22);
  const Signed s = sign(tx, "B", 5, {10, 20, 30});
  uint8_t expected[kMacBytes];
  mac_by_hand(k, "B", s.head, s.payload, expected);
  EXPECT_EQ(std::memcmp(expected, s.mac, kMacBytes), 0);

  // A receiver that starts (or restarts) after a capture was made has heard
  // nothing from that sender yet: the capture, 30 s or 2 min old, is refused
  // all the same, as is a counter far ahead of its clock.
  FleetAuth fresh(k, kChannels, 22);
  for (const int64_t age_us : {30'000'000LL, 120'000'000LL}) {
    Signed aged = s;
    aged.head.counter = wall_clock_us() - age_us;
    mac_by_hand(k, "B", aged.head, aged.payload, aged.mac);
    EXPECT_EQ(check(fresh, "B", aged), Verdict::kReplayed) << age_us;
  }
  Signed ahead = s;
  ahead.head.counter = wall_clock_us() + 120'000'000;
  mac_by_hand(k, "B", ahead.head, ahead.payload, ahead.mac);
  EXPECT_EQ(check(fresh, "B", ahead), Verdict::kReplayed);
  // Signed a moment before the receiver started: within the clock skew
  // allowed (FleetAuth::kClockSkewUs, the window that is left), it passes.
  EXPECT_EQ(check(fresh, "B", s), Verdict::kAccepted);
  // Sent after: passes, and from then on only the counter matters.
  EXPECT_EQ(check(fresh, "B", sign(tx, "B", 5, {1})), Verdict::kAccepted);
  EXPECT_EQ(check(fresh, "B", sign(tx, "B", 5, {2})), Verdict::kAccepted);
}

// A message signed with the counter `counter` (as a sender at that moment
// of its clock would stamp it).
Signed stamped(const FleetKey& k, const char* channel, int16_t sender, int64_t counter, uint8_t byte) {
  Signed s;
  s.payload = {byte};
  s.head.version = FleetAuth::kVersion, s.head.key_id = k.id, s.head.sender = sender, s.head.counter = counter;
  mac_by_hand(k, channel, s.head, s.payload, s.mac);
  return s;
}

TEST(FleetAuthTest, AMessageDeliveredOutOfOrderPassesOnceWithinTheWindowAndItsReplayNever) {
  const FleetKey k = key_of(7, 1);
  FleetAuth rx(k, kChannels, 22);
  const int64_t t = wall_clock_us();
  // Sent as 0, 1, 2, 3 (10 ms apart), delivered as 0, 3, 1, 2: all pass.
  const Signed m0 = stamped(k, "A", 4, t, 0), m1 = stamped(k, "A", 4, t + 10'000, 1),
               m2 = stamped(k, "A", 4, t + 20'000, 2), m3 = stamped(k, "A", 4, t + 30'000, 3);
  for (const Signed* m : {&m0, &m3, &m1, &m2}) EXPECT_EQ(check(rx, "A", *m), Verdict::kAccepted) << m->payload[0];
  EXPECT_EQ(rx.reordered(), 2);
  // Each again, in any order: a replay.
  for (const Signed* m : {&m1, &m3, &m0, &m2}) EXPECT_EQ(check(rx, "A", *m), Verdict::kReplayed) << m->payload[0];
  EXPECT_EQ(rx.counters().replayed, 4);
  // Another sender's, or another channel's, window is its own.
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 5, t + 5'000, 9)), Verdict::kAccepted);
  EXPECT_EQ(check(rx, "B", stamped(k, "B", 4, t + 5'000, 9)), Verdict::kAccepted);
  // Never seen, but older than the window (kReorderUs before the newest).
  const int64_t newest = t + 30'000;
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 4, newest - FleetAuth::kReorderUs - 1, 8)), Verdict::kReplayed);
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 4, t + 15'000, 7)), Verdict::kAccepted);  // between two seen: new
  EXPECT_EQ(rx.counters().replayed, 5);
  EXPECT_EQ(rx.reordered(), 3);
}

TEST(FleetAuthTest, TheWindowKeepsItsHighestCountersAndRefusesWhatLeftIt) {
  const FleetKey k = key_of(7, 1);
  FleetAuth rx(k, kChannels, 22);
  const int64_t t = wall_clock_us();
  // Every even counter of 2 * (slots + 1) in order: the window then holds the
  // slots highest below the newest; the lower ones left it (its floor).
  const int n = 2 * static_cast<int>(FleetAuth::kReorderSlots + 1);
  for (int i = 0; i < n; ++i)
    ASSERT_EQ(check(rx, "A", stamped(k, "A", 2, t + 2 * i, static_cast<uint8_t>(i))), Verdict::kAccepted);
  const int64_t newest = t + 2 * (n - 1);
  const int64_t lowest_kept = newest - 2 * static_cast<int64_t>(FleetAuth::kReorderSlots);
  // Every one of them again: refused, kept or not.
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, t + 2 * i, static_cast<uint8_t>(i))), Verdict::kReplayed) << i;
  // Odd counters never sent, the window full. Between the floor and the
  // lowest kept: it passes once and becomes the floor itself.
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, lowest_kept - 1, 1)), Verdict::kAccepted);
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, lowest_kept - 1, 1)), Verdict::kReplayed);
  // Above the lowest kept: it passes once, the lowest kept leaves the window.
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, lowest_kept + 1, 1)), Verdict::kAccepted);
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, lowest_kept + 1, 1)), Verdict::kReplayed);
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, lowest_kept, 1)), Verdict::kReplayed);
  // At or below the floor: refused, sent or not.
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 2, t + 1, 1)), Verdict::kReplayed);
  EXPECT_EQ(rx.reordered(), 2);
  EXPECT_EQ(rx.counters().replayed, n + 4);
}

// A receiver that restarts takes out of order only what was sent since it
// started (less the clock skew allowed), as for a sender's first message;
// a link whose messages supersede each other (the robot link) takes none.
TEST(FleetAuthTest, OutOfOrderAfterARestartOnlyWhatWasSentSinceAndNoneOnAnInOrderLink) {
  const FleetKey k = key_of(7, 1);
  FleetAuth rx(k, kChannels, 22);
  const int64_t t = wall_clock_us();                                                    // just after rx started
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 1, t - 1'500'000, 1)), Verdict::kAccepted);  // within the skew
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 1, t - 2'300'000, 2)), Verdict::kReplayed);  // before it started
  EXPECT_EQ(check(rx, "A", stamped(k, "A", 1, t - 1'800'000, 3)), Verdict::kAccepted);
  FleetAuth robot(k, kChannels, 22);
  robot.in_order_only();
  EXPECT_EQ(check(robot, "A", stamped(k, "A", 1, t + 20'000, 1)), Verdict::kAccepted);
  EXPECT_EQ(check(robot, "A", stamped(k, "A", 1, t + 10'000, 2)), Verdict::kReplayed);  // late
  EXPECT_EQ(check(robot, "A", stamped(k, "A", 1, t + 30'000, 3)), Verdict::kAccepted);
  EXPECT_EQ(robot.reordered(), 0);
}

// A link that reorders: 3 senders on 2 channels, a message every 1 ms
// each; the link holds a fifth of the messages back behind the next 1 to
// `hold_max` (seeded). Within the window nothing is lost and every replay is
// caught; held back past the window, a message is refused.
TEST(FleetAuthTest, AReorderingLinkLosesNothingWithinTheWindowAndItsReplaysAreAllCaught) {
  const FleetKey k = key_of(7, 1);
  const int64_t t = wall_clock_us() - 1'500'000;  // the first counters within kClockSkewUs of the receivers' start
  std::vector<std::pair<const char*, Signed>> sent;
  for (int i = 0; i < 3000; ++i)
    for (const char* channel : {"A", "B"})
      for (int16_t sender = -1; sender < 2; ++sender)
        sent.emplace_back(channel, stamped(k, channel, sender, t + 1000 * i, static_cast<uint8_t>(i)));
  uint64_t x = 12345;
  auto next = [&x]() { return (x = x * 6364136223846793005ULL + 1442695040888963407ULL) >> 33; };
  auto reorder = [&](std::size_t hold_max) {  // the order the link delivers `sent` in
    std::vector<std::size_t> order(sent.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    for (std::size_t i = 0; i + 1 < order.size(); ++i)
      if (next() % 5 == 0) {
        const std::size_t to = std::min(order.size() - 1, i + 1 + next() % hold_max);
        std::rotate(order.begin() + static_cast<std::ptrdiff_t>(i), order.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                    order.begin() + static_cast<std::ptrdiff_t>(to) + 1);
      }
    return order;
  };
  FleetAuth rx(k, kChannels, 22);
  for (std::size_t i : reorder(12)) ASSERT_EQ(check(rx, sent[i].first, sent[i].second), Verdict::kAccepted) << i;
  EXPECT_GT(rx.reordered(), 1000);
  for (std::size_t i : reorder(12)) EXPECT_EQ(check(rx, sent[i].first, sent[i].second), Verdict::kReplayed) << i;
  EXPECT_EQ(rx.counters().replayed, static_cast<int64_t>(sent.size()));

  // Held back behind up to 9000 others (1.5 s of this traffic): those that
  // fall out of the window (over kReorderUs late, or behind more than
  // kReorderSlots newer ones of their stream) are refused, the rest pass.
  FleetAuth slow(k, kChannels, 22);
  int64_t accepted = 0;
  for (std::size_t i : reorder(9000)) accepted += check(slow, sent[i].first, sent[i].second) == Verdict::kAccepted;
  const int64_t refused = slow.counters().replayed;
  EXPECT_GT(refused, 0);
  EXPECT_GT(slow.reordered(), 0);
  EXPECT_EQ(accepted + refused, static_cast<int64_t>(sent.size()));
  // Everything again, in another order of the slow link: nothing passes twice.
  for (std::size_t i : reorder(9000)) EXPECT_EQ(check(slow, sent[i].first, sent[i].second), Verdict::kReplayed) << i;
  EXPECT_EQ(slow.counters().replayed, refused + static_cast<int64_t>(sent.size()));
  std::printf(
      "reordering link, %zu messages: held back up to 12: %lld passed out of order, 0 refused; "
      "up to 9000: %lld passed out of order, %lld refused\n",
      sent.size(), static_cast<long long>(rx.reordered()), static_cast<long long>(slow.reordered()),
      static_cast<long long>(refused));
}

// A key file of `text` (mode 0600) in `dir` is refused by `load`, with an
// error that names `named`.
template <typename Load>
void refused(const std::string& dir, const std::string& text, const std::string& named, Load load) {
  const std::string p = dir + "/bad.key";
  std::filesystem::remove(p);
  std::ofstream(p) << text;
  ::chmod(p.c_str(), 0600);
  try {
    load(p);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
  }
}

TEST(FleetKeyTest, KeygenWritesA0600FileThatLoadsBackAndIsNeverOverwritten) {
  const std::string dir = ::testing::TempDir() + "/gather_key_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/fleet.key";
  std::filesystem::remove(path);
  const FleetKey k = generate_fleet_key(1234);
  write_fleet_key(path, k);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const FleetKey back = load_fleet_key(path);
  EXPECT_EQ(back.id, 1234);
  EXPECT_EQ(back.key, k.key);
  EXPECT_THROW(write_fleet_key(path, generate_fleet_key()), Error);
  EXPECT_EQ(load_fleet_key(path).key, k.key);
  EXPECT_NE(generate_fleet_key().key, k.key);

  ::chmod(path.c_str(), 0644);
  try {
    load_fleet_key(path);
    ADD_FAILURE() << "a world-readable key was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("chmod 600"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  ::chmod(path.c_str(), 0640);
  EXPECT_THROW(load_fleet_key(path), Error);

  auto bad = [&](const std::string& text, const std::string& named) { refused(dir, text, named, load_fleet_key); };
  const std::string hex(64, 'a');
  bad("key: " + hex + "\n", "key_id");
  bad("key_id: 3\n", "key");
  bad("key_id: 0\nkey: " + hex + "\n", "key_id");
  bad("key_id: 40000\nkey: " + hex + "\n", "key_id");
  bad("key_id: 3\nkey: " + hex.substr(2) + "\n", "key");
  bad("key_id: 3\nkey: " + std::string(64, 'g') + "\n", "key");
  bad("key_id: 3\nkey: " + hex + "\nsalt: 1\n", "salt");
  bad("just words\n", "bad.key:1");
  // A field given twice is refused, not the later line taken.
  bad("key_id: 3\nkey: " + hex + "\nkey_id: 4\n", "bad.key:3: key_id given twice");
  bad("key_id: 3\nkey: " + hex + "\nkey: " + std::string(64, 'b') + "\n", "bad.key:3: key given twice");
  EXPECT_THROW(load_fleet_key(dir + "/missing.key"), Error);
  std::filesystem::remove_all(dir);
}

// Per-link keys (docs/security.md): a team of a collector (agent 0) with
// workers 1 and 2, and a worker of the OC (3). Each holds only its links'
// keys, derived from the master.
struct LinkTeam {
  FleetKey master = key_of(7, 9);
  FleetLinks links{std::vector<int16_t>{-1, 0, 0, -1}};
  KeyRing ring(int16_t agent) const { return agent_key_ring(master, agent, links.peers(agent)); }
  static std::unique_ptr<FleetAuth> auth(std::optional<KeyRing> keys) {
    return std::make_unique<FleetAuth>(std::move(keys), PerLinkTags{}, kChannels, 8);
  }
  // The OC: the master, with the plan's links.
  std::unique_ptr<FleetAuth> oc() const {
    auto a = auth(KeyRing(master));
    a->set_links(links);
    return a;
  }
};

struct Tagged {
  EnvelopeHead head;
  std::vector<uint8_t> payload{1, 2, 3, 4};
  std::vector<int16_t> receivers;
  std::vector<uint8_t> tags;
};

// `sender`'s message signed by `a` for `receivers`; nullopt when `a` holds no key for one of them.
std::optional<Tagged> tagged(FleetAuth& a, int16_t sender, std::vector<int16_t> receivers) {
  Tagged t;
  t.receivers = std::move(receivers);
  t.tags.resize(t.receivers.size() * kTagBytes);
  if (!a.sign_tagged("A", sender, t.payload.data(), t.payload.size(), t.receivers.data(), t.receivers.size(), t.head,
                     t.tags.data()))
    return std::nullopt;
  return t;
}

Verdict check(FleetAuth& a, const Tagged& t) {
  return a.verify_tagged("A", t.head, t.payload.data(), t.payload.size(), t.receivers.data(), t.tags.data(),
                         t.receivers.size());
}

TEST(PerLinkKeysTest, LinkKeysAreTheKdfsAndTheSameBothWaysRound) {
  const LinkTeam team;
  EXPECT_EQ(link_key(team.master, 1, 0), link_key(team.master, 0, 1));
  EXPECT_NE(link_key(team.master, 0, 1), link_key(team.master, 0, 2));
  EXPECT_NE(link_key(team.master, -1, 1), link_key(team.master, 0, 1));
  EXPECT_NE(link_key(key_of(7, 8), 0, 1), link_key(team.master, 0, 1));
  KeyRing::Key by_hand{};  // libsodium's KDF, subkey (min + 1) << 16 | (max + 1), context "gthrLINK"
  crypto_kdf_derive_from_key(by_hand.data(), by_hand.size(), (0ull << 16) | 2ull, "gthrLINK", team.master.key.data());
  EXPECT_EQ(link_key(team.master, -1, 1), by_hand);
  // The robot link's key: the same from the master as in an agent's file, and not the master.
  EXPECT_EQ(robot_link_key(KeyRing(team.master)).key, robot_link_key(team.ring(2)).key);
  EXPECT_NE(robot_link_key(KeyRing(team.master)).key, team.master.key);
  EXPECT_EQ(team.links.peers(0), (std::vector<int16_t>{-1, 1, 2}));
  EXPECT_EQ(team.links.peers(1), (std::vector<int16_t>{-1, 0}));
  EXPECT_EQ(team.links.peers(3), (std::vector<int16_t>{-1}));
  EXPECT_EQ(team.links.peers(-1), (std::vector<int16_t>{0, 1, 2, 3}));
  EXPECT_TRUE(team.links.hears(2, 0, kBroadcast));
  EXPECT_FALSE(team.links.hears(2, 1, kBroadcast));  // a fellow worker's broadcast
  EXPECT_FALSE(team.links.hears(3, 0, kBroadcast));
  EXPECT_TRUE(team.links.hears(1, 0, 1));   // addressed to it, by its collector
  EXPECT_FALSE(team.links.hears(3, 0, 3));  // addressed to it, but from no link of its
  EXPECT_FALSE(team.links.hears(0, 0, kBroadcast));
}

// A tag by hand, as docs/security.md specifies it: BLAKE2b with a 16-byte
// output keyed with the link's key, of the message's BLAKE2b-256 digest
// (channel and its NUL, version, key id, sender, counter, payload size, big
// endian, then the payload) and the receiver's id (2 bytes, big endian).
TEST(PerLinkKeysTest, ATagIsTheDocumentedKeyedBlake2b) {
  const LinkTeam team;
  auto collector = LinkTeam::auth(team.ring(0));
  const std::optional<Tagged> t = tagged(*collector, 0, {kOc, 1});
  ASSERT_TRUE(t);
  EXPECT_EQ(t->head.version, FleetAuth::kTaggedVersion);
  std::vector<uint8_t> m{'A', 0};
  auto be = [&](uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) m.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  be(static_cast<uint16_t>(t->head.version), 2), be(static_cast<uint16_t>(t->head.key_id), 2),
      be(static_cast<uint16_t>(t->head.sender), 2);
  be(static_cast<uint64_t>(t->head.counter), 8), be(t->payload.size(), 4);
  m.insert(m.end(), t->payload.begin(), t->payload.end());
  uint8_t digest[32];
  crypto_generichash_blake2b(digest, sizeof digest, m.data(), m.size(), nullptr, 0);
  for (std::size_t i = 0; i < t->receivers.size(); ++i) {
    uint8_t in[34], tag[kTagBytes];
    std::memcpy(in, digest, 32);
    in[32] = static_cast<uint8_t>(static_cast<uint16_t>(t->receivers[i]) >> 8);
    in[33] = static_cast<uint8_t>(static_cast<uint16_t>(t->receivers[i]) & 0xff);
    const KeyRing::Key key = link_key(team.master, 0, t->receivers[i]);
    crypto_generichash_blake2b(tag, sizeof tag, in, sizeof in, key.data(), key.size());
    EXPECT_EQ(std::memcmp(tag, t->tags.data() + i * kTagBytes, kTagBytes), 0) << "receiver " << t->receivers[i];
  }
}

TEST(PerLinkKeysTest, EachReceiverChecksItsOwnTagAndTheMasterEveryOne) {
  const LinkTeam team;
  auto collector = LinkTeam::auth(team.ring(0)), worker1 = LinkTeam::auth(team.ring(1)),
       worker2 = LinkTeam::auth(team.ring(2)), oc_worker = LinkTeam::auth(team.ring(3)), oc = team.oc();
  const std::optional<Tagged> hello = tagged(*collector, 0, team.links.peers(0));
  ASSERT_TRUE(hello);
  EXPECT_EQ(check(*worker1, *hello), Verdict::kAccepted);
  EXPECT_EQ(check(*worker2, *hello), Verdict::kAccepted);
  EXPECT_EQ(check(*oc, *hello), Verdict::kAccepted);
  EXPECT_EQ(check(*oc_worker, *hello), Verdict::kNotForMe);  // not sent to it: not a refusal
  EXPECT_EQ(oc_worker->not_for_me(), 1);
  EXPECT_EQ(oc_worker->counters().total(), 0);
  EXPECT_EQ(check(*worker1, *hello), Verdict::kReplayed);
  // Every tag is its receiver's: worker 1's tag moved to worker 2 fails there.
  std::optional<Tagged> moved = tagged(*collector, 0, {1, 2});
  ASSERT_TRUE(moved);
  std::copy(moved->tags.begin(), moved->tags.begin() + kTagBytes, moved->tags.begin() + kTagBytes);
  EXPECT_EQ(check(*worker2, *moved), Verdict::kBadMac);
  EXPECT_EQ(check(*worker1, *moved), Verdict::kAccepted);
  // The payload changed on the way: every receiver refuses it.
  std::optional<Tagged> changed = tagged(*oc, kOc, {0, 1, 2, 3});
  ASSERT_TRUE(changed);
  changed->payload[0] ^= 1;
  for (FleetAuth* a : {collector.get(), worker1.get(), worker2.get(), oc_worker.get()})
    EXPECT_EQ(check(*a, *changed), Verdict::kBadMac);
  // The OC's broadcast, to all: everyone takes it.
  const std::optional<Tagged> plan = tagged(*oc, kOc, team.links.peers(kOc));
  ASSERT_TRUE(plan);
  for (FleetAuth* a : {collector.get(), worker1.get(), worker2.get(), oc_worker.get()})
    EXPECT_EQ(check(*a, *plan), Verdict::kAccepted);
  EXPECT_TRUE(oc->sees_all());
  EXPECT_FALSE(worker1->sees_all());
}

// A robot taken in the field (worker 1, with its own keys) speaks only as
// itself, and only to its links.
TEST(PerLinkKeysTest, ACapturedRobotSpeaksOnlyAsItselfToItsLinks) {
  const LinkTeam team;
  const KeyRing captured = team.ring(1);
  auto thief = LinkTeam::auth(captured);
  auto collector = LinkTeam::auth(team.ring(0)), worker2 = LinkTeam::auth(team.ring(2)),
       oc_worker = LinkTeam::auth(team.ring(3)), oc = team.oc();
  // As itself, to its links: taken.
  const std::optional<Tagged> own = tagged(*thief, 1, {kOc, 0});
  ASSERT_TRUE(own);
  EXPECT_EQ(check(*oc, *own), Verdict::kAccepted);
  EXPECT_EQ(check(*collector, *own), Verdict::kAccepted);
  // It holds no key to sign as anyone else, nor to an agent it has no link to.
  EXPECT_FALSE(tagged(*thief, 0, {2}));    // as its collector, to worker 2
  EXPECT_FALSE(tagged(*thief, kOc, {2}));  // as the OC
  EXPECT_FALSE(tagged(*thief, 1, {3}));    // to a worker of another
  // Its own keys under other names: every receiver refuses the tag.
  auto as = [&](int16_t agent, std::vector<int16_t> peers) {  // worker 1's link keys, filed as `agent`'s to `peers`
    KeyRing fake = captured;
    fake.agent = agent;
    fake.links.clear();
    for (std::size_t i = 0; i < peers.size(); ++i)
      fake.links.emplace_back(peers[i], captured.links[i % captured.links.size()].second);
    return LinkTeam::auth(fake);
  };
  auto fake_collector = as(0, {kOc, 2});
  const std::optional<Tagged> as_collector = tagged(*fake_collector, 0, {kOc, 2});
  ASSERT_TRUE(as_collector);
  EXPECT_EQ(check(*oc, *as_collector), Verdict::kBadMac);
  EXPECT_EQ(check(*worker2, *as_collector), Verdict::kBadMac);
  auto fake_oc_to_2 = as(2, {kOc});  // a tag for worker 2 as if from the OC
  const std::optional<Tagged> as_oc = tagged(*fake_oc_to_2, kOc, {2});
  ASSERT_TRUE(as_oc);
  EXPECT_EQ(check(*worker2, *as_oc), Verdict::kBadMac);
  auto fake_link = as(1, {3});  // as itself, to worker 3 (no link between them)
  const std::optional<Tagged> unlinked = tagged(*fake_link, 1, {3});
  ASSERT_TRUE(unlinked);
  EXPECT_EQ(check(*oc_worker, *unlinked), Verdict::kBadMac);
  EXPECT_EQ(oc->counters().bad_mac, 1);
  EXPECT_EQ(worker2->counters().bad_mac, 2);
  EXPECT_EQ(oc_worker->counters().bad_mac, 1);
}

// The master (the OC, the robot world, a replay) checks every tag, and
// derives keys only for the plan's links: a robot's good tag for its own
// link does not pass alongside one it cannot make, and an outsider cannot
// make it derive keys for pairs it names.
TEST(PerLinkKeysTest, TheMasterChecksEveryTagAndDerivesOnlyThePlansLinks) {
  const LinkTeam team;
  auto thief = LinkTeam::auth(team.ring(1)), worker2 = LinkTeam::auth(team.ring(2));
  auto oc = LinkTeam::auth(KeyRing(team.master));
  // Agent 1 signs as its collector for itself (it holds that link's key) and
  // for worker 2 (it does not): worker 2's tag is garbage.
  std::optional<Tagged> posing = tagged(*thief, 0, {1});
  ASSERT_TRUE(posing);
  posing->receivers.push_back(2);
  posing->tags.resize(2 * kTagBytes, 0x5a);
  EXPECT_EQ(check(*oc, *posing), Verdict::kBadMac);
  EXPECT_EQ(check(*worker2, *posing), Verdict::kBadMac);
  // Before the plan's links, the master knows the OC's links only: a
  // worker's message to its collector is not checked against any key.
  auto collector = LinkTeam::auth(team.ring(0));
  std::optional<Tagged> data = tagged(*thief, 1, {0});
  ASSERT_TRUE(data);
  EXPECT_EQ(check(*oc, *data), Verdict::kBadMac);
  oc->set_links(team.links);  // the plan's links: now it is
  std::optional<Tagged> again = tagged(*thief, 1, {0});
  ASSERT_TRUE(again);
  EXPECT_EQ(check(*oc, *again), Verdict::kAccepted);
  EXPECT_EQ(check(*collector, *again), Verdict::kAccepted);
  // A pair that is no link of the plan (workers 1 and 2): no key, whoever signs.
  Tagged unlinked = *again;
  unlinked.receivers = {2};
  EXPECT_EQ(check(*oc, unlinked), Verdict::kBadMac);
  EXPECT_FALSE(tagged(*oc, 1, {2}));  // nor can the master sign for it, once it knows the plan
  // And the OC's own broadcasts: every agent's tag good.
  std::optional<Tagged> tick = tagged(*oc, kOc, team.links.peers(kOc));
  ASSERT_TRUE(tick);
  EXPECT_EQ(check(*oc, *tick), Verdict::kAccepted);
}

TEST(PerLinkKeysTest, AnAgentsKeyFileHoldsItsLinksAndLoadsBack) {
  const std::string dir = ::testing::TempDir() + "/gather_agent_key_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  const LinkTeam team;
  const std::string path = dir + "/agent-0.key";
  std::filesystem::remove(path);
  write_key_ring(path, team.ring(0));
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const KeyRing back = load_key_ring(path);
  EXPECT_EQ(back.agent, 0);
  EXPECT_EQ(back.id, 7);
  EXPECT_EQ(back.key, robot_link_key(KeyRing(team.master)).key);
  ASSERT_EQ(back.links.size(), 3u);
  EXPECT_EQ(back.links[0].first, -1);
  EXPECT_EQ(back.links[0].second, link_key(team.master, 0, -1));
  EXPECT_EQ(back.links[2].second, link_key(team.master, 0, 2));
  std::ifstream file(path);
  const std::string body((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  char master_hex[2 * kKeyBytes + 1];
  sodium_bin2hex(master_hex, sizeof master_hex, team.master.key.data(), team.master.key.size());
  EXPECT_EQ(body.find(master_hex), std::string::npos);  // never the master
  try {
    load_fleet_key(path);  // the OC's side needs the master
    ADD_FAILURE() << "an agent's file taken as the master";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("agent 0's key file"), std::string::npos) << e.what();
  }
  auto bad = [&](const std::string& text, const std::string& named) { refused(dir, text, named, load_key_ring); };
  const std::string hex(64, 'a'), head = "key_id: 3\nagent: 2\nrobot_key: " + hex + "\n";
  bad(head, "link: missing");
  bad(head + "link: -1\n", "bad.key:4: link");
  bad(head + "link: x " + hex + "\n", "bad.key:4: link");
  bad(head + "link: -2 " + hex + "\n", "bad.key:4: link");
  bad(head + "link: -1 " + hex + "\nlink: -1 " + hex + "\n", "link -1 given twice");
  bad(head + "link: 2 " + hex + "\n", "a link to itself");
  bad(head + "link: -1 " + hex + "\nkey: " + hex + "\n", "holds no master key");
  bad("key_id: 3\nagent: 2\nlink: -1 " + hex + "\n", "robot_key: missing");
  bad("key_id: 3\nkey: " + hex + "\nlink: -1 " + hex + "\n", "agent: missing");
  bad("key_id: 3\nagent: 5000\n", "agent");
  std::filesystem::remove_all(dir);
}

TEST(FleetKeyTest, OptionsNeedAKeyOrAnExplicitInsecure) {
  EXPECT_THROW(fleet_key_from_options("", false, "test"), Error);
  EXPECT_THROW(fleet_key_from_options("some.key", true, "test"), Error);
  EXPECT_FALSE(fleet_key_from_options("", true, "test").has_value());
}

// The transport: a signed envelope on the wire passes; the same bytes
// changed anywhere, replayed, or carrying a payload whose sender differs
// from the signed one are dropped and counted, and nothing reaches the queue.
// `msg` (an LCM message) encoded, signed by `tx` (per-link mode) as
// `sender` on `channel` for `receivers`, in its envelope: the bytes a
// receiver hears.
template <typename Msg>
std::vector<uint8_t> enveloped(FleetAuth& tx, const char* channel, int16_t sender, const Msg& msg,
                               const std::vector<int16_t>& receivers = {kOc}) {
  std::vector<uint8_t> p(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(p.data(), 0, static_cast<int>(p.size()));
  gather_lcm::fleet_envelope_t e{};
  EnvelopeHead h;
  e.payload = p;
  e.receiver = receivers;
  e.tags.resize(receivers.size() * kTagBytes);
  EXPECT_TRUE(tx.sign_tagged(channel, sender, e.payload.data(), e.payload.size(), receivers.data(), receivers.size(), h,
                             e.tags.data()));
  e.version = h.version, e.key_id = h.key_id, e.sender = h.sender, e.counter = h.counter;
  e.size = static_cast<int32_t>(p.size());
  e.n_tags = static_cast<int16_t>(receivers.size());
  e.tag_bytes = static_cast<int32_t>(e.tags.size());
  std::vector<uint8_t> b(static_cast<std::size_t>(e.getEncodedSize()));
  e.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

const std::vector<std::string> kFleetChannels{kRequestChannel, kDataChannel,    kAckChannel,
                                              kStateChannel,   kPlanChannel,    kTickChannel,
                                              kReplyChannel,   kTimeAskChannel, kTimeChannel};

TEST(LcmFleetAuthTest, EnvelopesAreCheckedBeforeThePayloadIsDecoded) {
  const FleetKey key = key_of(7, 1);
  LcmFleet rx("memq://", "memq://", true, key, 20);
  FleetAuth tx(KeyRing(key), PerLinkTags{}, kFleetChannels, kMaxTeam + 1);
  auto wire = [&](int16_t payload_sender, int16_t envelope_sender) {
    gather_lcm::data_t d{};
    d.h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
    d.h.sender = payload_sender, d.h.dest = kOc, d.count = 0;
    return enveloped(tx, kDataChannel, envelope_sender, d);
  };
  const std::vector<uint8_t> good = wire(3, 3);
  rx.on_radio(kDataChannel, good.data(), static_cast<int>(good.size()));
  ASSERT_EQ(rx.radio().size(), 1u);
  rx.on_radio(kDataChannel, good.data(), static_cast<int>(good.size()));  // replayed
  EXPECT_EQ(rx.rejected().replayed, 1);
  // Every single bit flipped, one at a time: never accepted.
  const std::vector<uint8_t> fresh = wire(3, 3);
  for (std::size_t i = 0; i < fresh.size() * 8; ++i) {
    std::vector<uint8_t> b = fresh;
    b[i / 8] ^= static_cast<uint8_t>(1u << (i % 8));
    rx.on_radio(kDataChannel, b.data(), static_cast<int>(b.size()));
  }
  EXPECT_EQ(rx.radio().size(), 1u);
  EXPECT_EQ(rx.dropped(), 1 + static_cast<int64_t>(fresh.size() * 8));
  // Signed by a keyholder as agent 4 but claiming agent 3 inside.
  const std::vector<uint8_t> mismatched = wire(3, 4);
  rx.on_radio(kDataChannel, mismatched.data(), static_cast<int>(mismatched.size()));
  EXPECT_EQ(rx.rejected().wrong_sender, 1);
  // The fresh one itself still passes (nothing above moved its counter).
  rx.on_radio(kDataChannel, fresh.data(), static_cast<int>(fresh.size()));
  EXPECT_EQ(rx.radio().size(), 2u);
  // A declared payload size past the bytes that follow is refused before
  // anything is allocated for it.
  std::vector<uint8_t> huge = fresh;
  huge[8 + 14] = 0x7f;
  rx.on_radio(kDataChannel, huge.data(), static_cast<int>(huge.size()));
  EXPECT_EQ(rx.radio().size(), 2u);
  // The head and MAC of a good message with its payload cut out (size 0):
  // the MAC is checked over no bytes, never over the message decoded before.
  // Two messages with the same payload; the first is heard (the decoder then
  // holds its payload), the second arrives with its payload cut out. Were the
  // MAC checked over the bytes left from the first, it would pass.
  const std::vector<uint8_t> first = wire(3, 3), second = wire(3, 3);
  rx.on_radio(kDataChannel, first.data(), static_cast<int>(first.size()));
  ASSERT_EQ(rx.radio().size(), 3u);
  gather_lcm::fleet_envelope_t e;
  ASSERT_EQ(e.decode(second.data(), 0, static_cast<int>(second.size())), static_cast<int>(second.size()));
  e.size = 0, e.payload.clear();
  std::vector<uint8_t> empty(static_cast<std::size_t>(e.getEncodedSize()));
  e.encode(empty.data(), 0, static_cast<int>(empty.size()));
  const int64_t bad_mac = rx.rejected().bad_mac, undecodable = rx.refused().undecodable;
  rx.on_radio(kDataChannel, empty.data(), static_cast<int>(empty.size()));
  EXPECT_EQ(rx.rejected().bad_mac, bad_mac + 1);
  EXPECT_EQ(rx.refused().undecodable, undecodable);
  rx.on_radio(kDataChannel, second.data(), static_cast<int>(second.size()));  // its counter was not used up
  EXPECT_EQ(rx.radio().size(), 4u);
}

// A captured robot's good tags for its own links, on a message that claims
// another sender or other addresses (its collector's data for the OC, the
// OC's tick for all, its collector's reply), are dropped by the OC (the
// master): the receivers must be those the message's kind and addresses give.
TEST(LcmFleetAuthTest, GoodTagsForOthersThanTheAddressesSayAreDropped) {
  const FleetKey master = key_of(7, 1);
  LcmFleet rx("memq://", "memq://", true, master, 20);
  std::vector<int16_t> upstream(20, -1);
  upstream[1] = 0, upstream[2] = 0;  // workers 1 and 2 of collector 0
  std::vector<uint8_t> collectors(20, 0);
  collectors[0] = 1;
  const FleetLinks links(upstream);
  rx.set_team(20, collectors, links);
  FleetAuth thief(agent_key_ring(master, 1, links.peers(1)), PerLinkTags{}, kFleetChannels, kMaxTeam + 1);
  gather_lcm::data_t d{};
  d.h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  d.h.sender = 0, d.h.dest = kOc, d.count = 0;
  const std::vector<uint8_t> as_collector = enveloped(thief, kDataChannel, 0, d, {1});
  rx.on_radio(kDataChannel, as_collector.data(), static_cast<int>(as_collector.size()));
  EXPECT_EQ(rx.radio().size(), 0u);
  EXPECT_EQ(rx.rejected().bad_mac, 1);
  gather_lcm::tick_t t{};
  t.schema_version = gather_lcm::tick_t::SCHEMA_VERSION, t.tick = 5;
  const std::vector<uint8_t> as_oc = enveloped(thief, kTickChannel, kOc, t, {1});
  rx.on_clock(kTickChannel, as_oc.data(), static_cast<int>(as_oc.size()));
  EXPECT_EQ(rx.ticks().size(), 0u);
  EXPECT_EQ(rx.rejected().bad_mac, 2);
  // What it may say, as itself, to its links: taken.
  d.h.sender = 1, d.h.dest = kOc;
  const std::vector<uint8_t> own = enveloped(thief, kDataChannel, 1, d, {kOc});
  rx.on_radio(kDataChannel, own.data(), static_cast<int>(own.size()));
  EXPECT_EQ(rx.radio().size(), 1u);
  // Its broadcast to the OC alone (not to its collector as well): dropped.
  d.h.dest = kBroadcast;
  const std::vector<uint8_t> narrow = enveloped(thief, kDataChannel, 1, d, {kOc});
  rx.on_radio(kDataChannel, narrow.data(), static_cast<int>(narrow.size()));
  EXPECT_EQ(rx.radio().size(), 1u);
  EXPECT_EQ(rx.rejected().bad_mac, 3);
  EXPECT_EQ(rx.rejected().total(), 3);
}

// A message of a kind its sender's role never sends is dropped however well
// it is signed: a worker's request or ack, the OC's data or state.
TEST(LcmFleetAuthTest, AKindItsSendersRoleNeverSendsIsDroppedAsWrongSender) {
  const FleetKey key = key_of(7, 1);
  LcmFleet rx("memq://", "memq://", true, key, 20);
  std::vector<uint8_t> collectors(20, 0);
  collectors[5] = 1;  // agent 5 collects, the others work
  rx.set_team(20, collectors);
  FleetAuth tx(KeyRing(key), PerLinkTags{}, kFleetChannels, kMaxTeam + 1);
  auto seal = [&](const char* channel, int16_t sender, auto msg) {
    msg.h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
    msg.h.sender = sender, msg.h.dest = gather_lcm::header_t::BROADCAST;
    const std::vector<uint8_t> b =
        enveloped(tx, channel, sender, msg, {sender == kOc ? int16_t{0} : kOc});  // the OC's to agent 0
    rx.on_radio(channel, b.data(), static_cast<int>(b.size()));
  };
  gather_lcm::request_t request{};
  request.parts = 1;
  gather_lcm::agent_state_t state{};
  state.role = gather_lcm::agent_state_t::ROLE_WORKER;
  const gather_lcm::ack_t ack{};
  const gather_lcm::data_t data{};
  struct Case {
    const char* what;
    std::function<void()> send;
    bool passes;
  };
  const std::vector<Case> cases{
      {"the OC's request", [&] { seal(kRequestChannel, kOc, request); }, true},
      {"a collector's request", [&] { seal(kRequestChannel, 5, request); }, true},
      {"a worker's request", [&] { seal(kRequestChannel, 3, request); }, false},
      {"the OC's ack", [&] { seal(kAckChannel, kOc, ack); }, true},
      {"a collector's ack", [&] { seal(kAckChannel, 5, ack); }, true},
      {"a worker's ack", [&] { seal(kAckChannel, 3, ack); }, false},
      {"a worker's data", [&] { seal(kDataChannel, 3, data); }, true},
      {"a collector's data", [&] { seal(kDataChannel, 5, data); }, true},
      {"the OC's data", [&] { seal(kDataChannel, kOc, data); }, false},
      {"a worker's state", [&] { seal(kStateChannel, 3, state); }, true},
      {"a collector's state", [&] { seal(kStateChannel, 5, state); }, true},
      {"the OC's state", [&] { seal(kStateChannel, kOc, state); }, false},
  };
  for (const Case& c : cases) {
    const std::size_t heard = rx.radio().size();
    const int64_t wrong = rx.rejected().wrong_sender;
    c.send();
    EXPECT_EQ(rx.radio().size(), heard + (c.passes ? 1 : 0)) << c.what;
    EXPECT_EQ(rx.rejected().wrong_sender, wrong + (c.passes ? 0 : 1)) << c.what;
  }
  EXPECT_EQ(rx.rejected().total(), 4);
  EXPECT_FALSE(rx.may_send(3, Kind::kRequest));
  EXPECT_TRUE(rx.may_send(5, Kind::kRequest));
  // Roles unknown (no plan yet): an agent may send any kind, the OC only its own.
  rx.set_team(20);
  EXPECT_TRUE(rx.may_send(3, Kind::kRequest));
  EXPECT_FALSE(rx.may_send(kOc, Kind::kData));
}

}  // namespace
}  // namespace agent
}  // namespace gather
