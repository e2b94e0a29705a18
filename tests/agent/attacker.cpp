// gather_attacker: a hostile process on the fleet's LCM network (tests only;
// run it inside tools/netns-run, as tests/e2e/runtime_e2e.py does). It has
// no fleet key. It listens until the mission's clock ticks, keeping the
// messages it hears, then sends `--each` messages of each attack:
//   forged        agent states and data deliveries for random agents, signed
//                 with a key of its own under the fleet's key id -> bad MAC
//   other_key     requests signed under another key id        -> unknown key
//   unsigned      data deliveries without a signature           -> unsigned
//   replayed      captured valid messages sent again later (delivery acks
//                 among them), each older than the reorder window
//                 behind a newer one of its sender        -> replayed
//   tampered      captured valid messages with one bit flipped in the
//                 payload                                      -> bad MAC
//   impersonated  captured valid messages with another agent's id as the
//                 sender                                       -> bad MAC
// With --captured FILE (an agent's own key file: a robot taken in the field,
// a worker of a collector) it also sends, as that robot would, `--each` / 4
// of each:
//   as its collector  a request, tagged with its own keys    -> bad MAC
//   as another worker a data delivery, so tagged               -> bad MAC
//   as the OC         a request declaring a live agent dead    -> bad MAC
//   as its collector, data for the OC, and as the OC, a tick for all, with
//                     good tags for itself only               -> bad MAC
//                     (checked by the OC, and by itself)
//   as itself         a request declaring a live agent dead, a plan and a
//                     tick, to its links (the OC, its collector),
//                     well signed                              -> wrong sender
// (its tags for every agent but itself: its own process would take a tag
// made with its own keys; in the field, that robot is the attacker).
// With --captured FILE --claim G1,G2,... it does only this, once it heard a
// request of the OC: as itself, well signed for the OC, it hands in a
// measurement of each goal listed (goals of other workers' segments, that
// it never measured) -> refused by the OC as invalid items (mission.yaml
// oc.invalid_items), and writes `claims: N` to --out.
// and writes what it sent to --out (YAML): per reason, what the OC must
// have rejected (it holds the master: it checks every message) and what
// each agent must have (a message under the fleet's key id only where it
// carries a tag for that agent: per-link keys, docs/security.md; agents do
// not hear the tick replies' URL).
#include <lcm/lcm.h>
#include <unistd.h>

#include <gather_lcm/agent_state_t.hpp>
#include <gather_lcm/data_t.hpp>
#include <gather_lcm/fleet_envelope_t.hpp>
#include <gather_lcm/plan_t.hpp>
#include <gather_lcm/request_t.hpp>
#include <gather_lcm/tick_t.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"

namespace {

using gather::agent::EnvelopeHead;
using gather::agent::FleetAuth;
using gather::agent::FleetKey;
using gather::agent::KeyRing;

struct Captured {
  std::string channel;
  std::vector<uint8_t> bytes;
  bool reply = false;  // heard on the replies' URL
  int16_t sender = 0;  // the envelope's
  int64_t counter = 0;
  std::vector<int16_t> receivers;                // the agents (and the OC, -1) it carries a tag for
  std::size_t payload_at = 0, payload_size = 0;  // where its payload is in `bytes`
};

// The captures a replay of which every receiver refuses: those whose sender
// sent a newer message on their channel, to each of the capture's
// receivers (the OC takes every message), more than the reorder window
// later (FleetAuth::kReorderUs). A replay of a newer capture that some
// receiver never took (it was not yet listening) would pass there once, as
// a late delivery does.
std::vector<const Captured*> replayable(const std::vector<Captured>& captured) {
  std::map<std::tuple<std::string, int16_t, int16_t>, int64_t> newest;  // channel, sender, receiver (-1: the OC)
  for (const Captured& c : captured) {
    int64_t& oc = newest[{c.channel, c.sender, -1}];
    oc = std::max(oc, c.counter);
    for (int16_t r : c.receivers) {
      int64_t& n = newest[{c.channel, c.sender, r}];
      n = std::max(n, c.counter);
    }
  }
  std::vector<const Captured*> out;
  for (const Captured& c : captured) {
    const int64_t before = c.counter + FleetAuth::kReorderUs + 200'000;
    bool refused = newest[{c.channel, c.sender, -1}] > before;
    for (int16_t r : c.receivers) refused = refused && newest[{c.channel, c.sender, r}] > before;
    if (refused) out.push_back(&c);
  }
  return out;
}

struct State {
  std::vector<Captured> captured;
  bool ticking = false;
  bool requested = false;  // a request of the OC heard
  bool capturing = true;
  int16_t key_id = 0;
};

void on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* user, bool reply) {
  State& s = *static_cast<State*>(user);
  if (!s.capturing) return;
  if (std::strcmp(channel, gather::agent::kTickChannel) == 0) s.ticking = true;
  if (std::strcmp(channel, gather::agent::kRequestChannel) == 0) s.requested = true;
  // The clock exchange's channels are checked for key and MAC only, by
  // design (docs/security.md): a replay there is harmless and not counted.
  if (std::strcmp(channel, gather::agent::kTimeChannel) == 0 ||
      std::strcmp(channel, gather::agent::kTimeAskChannel) == 0)
    return;
  gather_lcm::fleet_envelope_t e;
  if (e.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) != static_cast<int>(rbuf->data_size)) return;
  if (e.key_id != 0) s.key_id = e.key_id;
  if (s.captured.size() < 20000)
    s.captured.push_back({channel,
                          std::vector<uint8_t>(static_cast<const uint8_t*>(rbuf->data),
                                               static_cast<const uint8_t*>(rbuf->data) + rbuf->data_size),
                          reply, e.sender, e.counter, e.receiver, 8 + 2 + 2 + 2 + 8 + 4,
                          static_cast<std::size_t>(e.size)});
}
void on_radio(const lcm_recv_buf_t* rbuf, const char* channel, void* user) { on_message(rbuf, channel, user, false); }
void on_reply(const lcm_recv_buf_t* rbuf, const char* channel, void* user) { on_message(rbuf, channel, user, true); }

template <typename T>
std::vector<uint8_t> encoded(const T& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

// `payload` in an envelope signed by `auth` (a key the fleet does not
// have) for `receivers`, its key id then set to `key_id`.
std::vector<uint8_t> wrap(FleetAuth& auth, const char* channel, int16_t sender, const std::vector<uint8_t>& payload,
                          int16_t key_id, const std::vector<int16_t>& receivers) {
  gather_lcm::fleet_envelope_t e{};
  EnvelopeHead h;
  e.payload = payload;
  e.receiver = receivers;
  e.tags.resize(receivers.size() * gather::agent::kTagBytes);
  auth.sign_tagged(channel, sender, e.payload.data(), e.payload.size(), receivers.data(), receivers.size(), h,
                   e.tags.data());
  e.version = h.version, e.key_id = key_id, e.sender = h.sender, e.counter = h.counter;
  e.size = static_cast<int32_t>(payload.size());
  e.n_tags = static_cast<int16_t>(receivers.size());
  e.tag_bytes = static_cast<int32_t>(e.tags.size());
  return encoded(e);
}

gather_lcm::header_t header(int16_t sender, int16_t dest, double t) {
  gather_lcm::header_t h{};
  h.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  h.sender = sender, h.dest = dest, h.seq = 1000000, h.tick = -1, h.t = t, h.request = 0;
  return h;
}

}  // namespace

int main(int argc, char** argv) {
  std::string url = "udpm://239.255.76.67:7667?ttl=0", reply_url, out, captured_file, claim;
  int each = 40, team = 20;
  double at_x = 0.0, at_y = 0.0;
  double wait_s = 60.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--lcm-url")
      url = v;
    else if (a == "--reply-url")
      reply_url = v;
    else if (a == "--out")
      out = v;
    else if (a == "--each")
      each = std::atoi(v.c_str());
    else if (a == "--captured")
      captured_file = v;
    else if (a == "--team")
      team = std::atoi(v.c_str());
    else if (a == "--wait")
      wait_s = std::atof(v.c_str());
    else if (a == "--claim")
      claim = v;
    else if (a == "--at")  // x,y [m]: where it says it is (the range gate takes the sender's word)
      std::sscanf(v.c_str(), "%lf,%lf", &at_x, &at_y);
    else {
      std::fprintf(stderr, "gather_attacker: unknown flag %s\n", a.c_str());
      return 2;
    }
  }
  if (out.empty() || each < 1 || team < 2) {
    std::fprintf(stderr,
                 "usage: gather_attacker --out FILE [--lcm-url URL] [--reply-url URL] [--each N] [--team N] [--wait S] "
                 "[--captured AGENT_KEY_FILE [--claim G1,G2,... [--at X,Y]]]\n");
    return 2;
  }
  std::vector<int32_t> claims;
  for (std::size_t from = 0; !claim.empty() && from <= claim.size();) {
    const std::size_t comma = std::min(claim.find(',', from), claim.size());
    claims.push_back(std::atoi(claim.substr(from, comma - from).c_str()));
    from = comma + 1;
  }
  if (!claims.empty() && captured_file.empty()) {
    std::fprintf(stderr, "gather_attacker: --claim needs --captured\n");
    return 2;
  }
  if (reply_url.empty()) reply_url = gather::agent::LcmFleet::reply_url_for(url);
  // The captured robot's keys: a worker of a collector (its links: the OC and that collector).
  std::optional<gather::agent::KeyRing> stolen;
  int16_t collector = -1;
  if (!captured_file.empty()) {
    try {
      stolen = gather::agent::load_key_ring(captured_file);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "gather_attacker: %s\n", e.what());
      return 2;
    }
    for (const auto& l : stolen->links)
      if (l.first >= 0) collector = l.first;
    if (stolen->master() || stolen->links.size() != 2 || collector < 0) {
      std::fprintf(stderr, "gather_attacker: %s: not the keys of a worker of a collector\n", captured_file.c_str());
      return 2;
    }
  }
  lcm_t* radio = lcm_create(url.c_str());
  lcm_t* replies = lcm_create(reply_url.c_str());
  if (!radio || !replies) {
    std::fprintf(stderr, "gather_attacker: cannot open %s or %s\n", url.c_str(), reply_url.c_str());
    return 2;
  }
  State s;
  lcm_subscription_set_queue_capacity(lcm_subscribe(radio, ".*", on_radio, &s), 100000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(replies, ".*", on_reply, &s), 100000);

  const auto t0 = std::chrono::steady_clock::now();
  if (!claims.empty()) {  // claims of goals it never measured, as itself, once the OC has requested
    while (!s.requested) {
      if (std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(wait_s)) {
        std::fprintf(stderr, "gather_attacker: no request of the OC heard within %.0f s\n", wait_s);
        return 1;
      }
      lcm_handle_timeout(radio, 5);
      lcm_handle_timeout(replies, 0);
    }
    s.capturing = false;
    FleetAuth itself(*stolen, gather::agent::PerLinkTags{}, {gather::agent::kDataChannel}, gather::agent::kMaxTeam + 1);
    for (std::size_t i = 0; i < claims.size(); ++i) {
      gather_lcm::data_t d{};
      d.h = header(stolen->agent, gather::agent::kOc, 1.0), d.count = 1;
      d.h.seq = static_cast<int32_t>(2000000 + i), d.h.x = at_x, d.h.y = at_y;
      d.items[0].key = claims[i], d.items[0].kind = 1, d.items[0].by = stolen->agent, d.items[0].at = 1.0;
      d.items[0].picked_up_by = -1, d.items[0].picked_up_at = -1.0, d.items[0].deadline = 1e9;
      const std::vector<uint8_t> bytes =
          wrap(itself, gather::agent::kDataChannel, stolen->agent, encoded(d), s.key_id, {gather::agent::kOc});
      lcm_publish(radio, gather::agent::kDataChannel, bytes.data(), static_cast<unsigned>(bytes.size()));
      ::usleep(20000);
    }
    std::ofstream f(out);
    f << "# gather_attacker: claims of goals it never measured, as robot " << stolen->agent << "\n";
    f << "claims: " << claims.size() << "\n";
    std::printf("gather_attacker: %zu claims sent as robot %d -> %s\n", claims.size(), stolen->agent, out.c_str());
    lcm_destroy(radio);
    lcm_destroy(replies);
    return f ? 0 : 1;
  }
  // Listen until the clock ticks and some traffic (acks among it) is kept.
  // Checked a few times a second: enough captures a replay of which every
  // receiver refuses, delivery acks among them.
  std::size_t old_count = 0;
  int old_acks = 0;
  auto next_check = std::chrono::steady_clock::now();
  auto ready = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (!s.ticking || s.captured.size() < 400 || now < next_check) return false;
    next_check = now + std::chrono::milliseconds(200);
    const std::vector<const Captured*> old = replayable(s.captured);
    old_count = old.size();
    old_acks = static_cast<int>(std::count_if(
        old.begin(), old.end(), [](const Captured* c) { return c->channel == gather::agent::kAckChannel; }));
    return old_acks >= 5 && old_count >= 100;
  };
  while (!ready()) {
    if (std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(wait_s)) {
      std::fprintf(stderr,
                   "gather_attacker: no fleet traffic to attack within %.0f s (%zu messages, %zu replayable, %d acks "
                   "among them)\n",
                   wait_s, s.captured.size(), old_count, old_acks);
      return 1;
    }
    lcm_handle_timeout(radio, 5);
    lcm_handle_timeout(replies, 0);
  }
  // Stop keeping what it hears (its own messages come back to it), and let
  // every receiver take in the originals before anything is replayed.
  s.capturing = false;
  std::vector<Captured> kept = s.captured;
  ::usleep(300000);

  std::mt19937_64 rng(12345);
  int16_t f_captured = -1;
  FleetAuth own(gather::agent::KeyRing(gather::agent::generate_fleet_key()), gather::agent::PerLinkTags{},
                {gather::agent::kRequestChannel, gather::agent::kDataChannel, gather::agent::kAckChannel,
                 gather::agent::kStateChannel, gather::agent::kPlanChannel, gather::agent::kTickChannel,
                 gather::agent::kReplyChannel},
                gather::agent::kMaxTeam + 1);
  // Tags for everyone: every agent checks (and refuses) what it carries a tag for.
  std::vector<int16_t> everyone{gather::agent::kOc};
  for (int a = 0; a < team; ++a) everyone.push_back(static_cast<int16_t>(a));
  // Expected rejections: [reason] for the OC and for each agent.
  std::map<std::string, long> oc;
  std::vector<std::map<std::string, long>> agent(static_cast<std::size_t>(team));
  // `counted`: the agents that check it (those it carries a tag for; every
  // one for another key id or none, which are refused before any tag is looked at).
  auto send = [&](const Captured& c, const std::vector<uint8_t>& bytes, const std::string& reason,
                  const std::vector<int16_t>& counted) {
    lcm_publish(c.reply ? replies : radio, c.channel.c_str(), bytes.data(), static_cast<unsigned>(bytes.size()));
    ++oc[reason];
    if (!c.reply)
      for (int16_t r : counted)
        if (r >= 0 && r < team) ++agent[static_cast<std::size_t>(r)][reason];
    ::usleep(2000);  // a gentle rate: nothing is lost to full socket buffers
  };
  std::vector<const Captured*> radio_msgs, ack_msgs, old_msgs = replayable(kept);
  for (const Captured& c : kept)
    if (!c.reply && c.payload_size > 0) radio_msgs.push_back(&c);
  for (const Captured* c : old_msgs)
    if (c->channel == gather::agent::kAckChannel) ack_msgs.push_back(c);
  auto fresh = [](const char* channel) {  // a message of its own on the radio
    Captured c;
    c.channel = channel;
    return c;
  };
  auto pick = [&](const std::vector<const Captured*>& v) -> const Captured& { return *v[rng() % v.size()]; };
  for (int i = 0; i < each; ++i) {
    const int16_t victim = static_cast<int16_t>(rng() % static_cast<uint64_t>(team));
    // (a) forged agent states and data deliveries, and requests under another key id, and unsigned data.
    gather_lcm::agent_state_t st{};
    st.h = header(victim, gather::agent::kBroadcast, 10.0 + i), st.role = gather_lcm::agent_state_t::ROLE_WORKER;
    send(fresh(gather::agent::kStateChannel),
         wrap(own, gather::agent::kStateChannel, victim, encoded(st), s.key_id, everyone), "bad_mac", everyone);
    gather_lcm::data_t d{};
    d.h = header(victim, gather::agent::kOc, 10.0 + i), d.count = 1;
    d.items[0].key = 7 + i, d.items[0].kind = 1, d.items[0].by = victim, d.items[0].at = 5.0,
    d.items[0].picked_up_by = -1;
    send(fresh(gather::agent::kDataChannel),
         wrap(own, gather::agent::kDataChannel, victim, encoded(d), s.key_id, everyone), "bad_mac", everyone);
    gather_lcm::request_t r{};
    r.h = header(gather::agent::kOc, gather::agent::kBroadcast, 10.0 + i), r.request = 50 + i, r.parts = 1;
    send(fresh(gather::agent::kRequestChannel),
         wrap(own, gather::agent::kRequestChannel, gather::agent::kOc, encoded(r),
              static_cast<int16_t>(s.key_id % 32767 + 1), {0}),
         "unknown_key", everyone);
    send(fresh(gather::agent::kDataChannel), wrap(own, gather::agent::kDataChannel, victim, encoded(d), 0, {}),
         "unsigned", everyone);
    // (b) replays, delivery acks half of them.
    const Captured& old = (i % 2 == 0 && !ack_msgs.empty()) ? pick(ack_msgs) : pick(old_msgs);
    send(old, old.bytes, "replayed", old.receivers);
    // (c) one bit flipped in the payload.
    const Captured& valid = pick(radio_msgs);
    std::vector<uint8_t> flipped = valid.bytes;
    flipped[valid.payload_at + rng() % valid.payload_size] ^= static_cast<uint8_t>(1u << (rng() % 8));
    send(valid, flipped, "bad_mac", valid.receivers);
    // (d) a valid radio message passed off as another agent's.
    const Captured& mine = pick(radio_msgs);
    std::vector<uint8_t> other = mine.bytes;
    const int16_t was = static_cast<int16_t>(other[8 + 4] << 8 | other[8 + 5]);
    const int16_t as =
        static_cast<int16_t>((was + 1 + static_cast<int>(rng() % static_cast<uint64_t>(team - 1))) % team);
    other[8 + 4] = static_cast<uint8_t>(static_cast<uint16_t>(as) >> 8), other[8 + 5] = static_cast<uint8_t>(as & 0xff);
    send(mine, other, "bad_mac", mine.receivers);
  }
  if (stolen) {
    const int16_t thief = stolen->agent;
    const KeyRing::Key& to_oc = stolen->links[0].second;  // its key with the OC (links by peer: -1 first)
    std::vector<int16_t> others;                          // every agent but itself
    for (int a = 0; a < team; ++a)
      if (a != thief) others.push_back(static_cast<int16_t>(a));
    std::vector<int16_t> oc_and_others{gather::agent::kOc};
    oc_and_others.insert(oc_and_others.end(), others.begin(), others.end());
    // Its own keys, filed as `as`'s links to `to` (for the OC, -1: as a master).
    auto posing = [&](int16_t as, const std::vector<int16_t>& to) {
      KeyRing fake;
      fake.id = stolen->id, fake.agent = as, fake.key = to_oc;
      if (as >= 0)
        for (int16_t r : to)
          if (r != as) fake.links.emplace_back(r, to_oc);
      std::sort(fake.links.begin(), fake.links.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      return std::make_unique<FleetAuth>(
          fake, gather::agent::PerLinkTags{},
          std::vector<std::string>{gather::agent::kRequestChannel, gather::agent::kDataChannel,
                                   gather::agent::kPlanChannel, gather::agent::kTickChannel},
          gather::agent::kMaxTeam + 1);
    };
    FleetAuth itself(*stolen, gather::agent::PerLinkTags{},
                     {gather::agent::kRequestChannel, gather::agent::kDataChannel, gather::agent::kPlanChannel,
                      gather::agent::kTickChannel},
                     gather::agent::kMaxTeam + 1);
    // A live agent (neither itself nor its collector) to declare dead, and to pose as.
    int16_t peer = static_cast<int16_t>((thief + 1) % team);
    while (peer == thief || peer == collector) peer = static_cast<int16_t>((peer + 1) % team);
    auto as_collector = posing(collector, oc_and_others), as_peer = posing(peer, oc_and_others),
         as_oc = posing(gather::agent::kOc, others);
    // Its wrap(), but with the fleet's key id: a tag made with a key of the fleet.
    auto sealed = [&](FleetAuth& by, const char* channel, int16_t sender, const std::vector<uint8_t>& payload,
                      const std::vector<int16_t>& to) { return wrap(by, channel, sender, payload, s.key_id, to); };
    const std::vector<int16_t> links{gather::agent::kOc, collector};
    for (int i = 0; i < std::max(1, each / 4); ++i) {
      gather_lcm::request_t r{};
      r.h = header(collector, gather::agent::kBroadcast, 20.0 + i), r.request = 60 + i, r.parts = 1;
      send(fresh(gather::agent::kRequestChannel),
           sealed(*as_collector, gather::agent::kRequestChannel, collector, encoded(r), oc_and_others), "bad_mac",
           others);
      gather_lcm::data_t d{};
      d.h = header(peer, gather::agent::kOc, 20.0 + i), d.count = 1;
      d.items[0].key = i, d.items[0].kind = 1, d.items[0].by = peer, d.items[0].at = 5.0, d.items[0].picked_up_by = -1;
      send(fresh(gather::agent::kDataChannel),
           sealed(*as_peer, gather::agent::kDataChannel, peer, encoded(d), oc_and_others), "bad_mac", others);
      gather_lcm::request_t death{};
      death.h = header(gather::agent::kOc, gather::agent::kBroadcast, 20.0 + i), death.request = 0, death.parts = 1;
      death.n_dead = 1, death.dead = {peer};
      send(fresh(gather::agent::kRequestChannel),
           sealed(*as_oc, gather::agent::kRequestChannel, gather::agent::kOc, encoded(death), others), "bad_mac",
           others);
      // Good tags, for itself only (it holds its links' keys), on messages as
      // its collector to the OC and as the OC to all: their receivers are not
      // those their addresses give, and every receiver that checks them (the
      // OC, which checks every tag; itself, whose tag is good) drops them.
      const std::vector<int16_t> just_itself{thief};
      gather_lcm::data_t handed{};
      handed.h = header(collector, gather::agent::kOc, 20.0 + i), handed.count = 1;
      handed.items[0] = d.items[0], handed.items[0].picked_up_by = collector;
      send(fresh(gather::agent::kDataChannel),
           sealed(itself, gather::agent::kDataChannel, collector, encoded(handed), just_itself), "bad_mac",
           just_itself);
      gather_lcm::tick_t fake_tick{};
      fake_tick.schema_version = gather_lcm::tick_t::SCHEMA_VERSION, fake_tick.tick = 2000000 + i;
      send(fresh(gather::agent::kTickChannel),
           sealed(itself, gather::agent::kTickChannel, gather::agent::kOc, encoded(fake_tick), just_itself), "bad_mac",
           just_itself);
      // As itself, well signed, what its role never sends: dropped as wrong sender by its links.
      death.h.sender = thief;
      send(fresh(gather::agent::kRequestChannel),
           sealed(itself, gather::agent::kRequestChannel, thief, encoded(death), links), "wrong_sender", links);
      gather_lcm::plan_t plan{};
      plan.schema_version = gather_lcm::plan_t::SCHEMA_VERSION, plan.agents = team, plan.cycles = 1;
      send(fresh(gather::agent::kPlanChannel), sealed(itself, gather::agent::kPlanChannel, thief, encoded(plan), links),
           "wrong_sender", links);
      gather_lcm::tick_t tick{};
      tick.schema_version = gather_lcm::tick_t::SCHEMA_VERSION, tick.tick = 1000000 + i, tick.done = true;
      send(fresh(gather::agent::kTickChannel), sealed(itself, gather::agent::kTickChannel, thief, encoded(tick), links),
           "wrong_sender", links);
    }
    f_captured = thief;
  }
  // Its own copies come back to it: drain them.
  for (int i = 0; i < 100; ++i) lcm_handle_timeout(radio, 1), lcm_handle_timeout(replies, 0);
  std::ofstream f(out);
  f << "# gather_attacker: messages sent, by the reason they must be rejected for\n";
  f << "captured: " << kept.size() << "\n";
  if (f_captured >= 0) f << "robot: " << f_captured << "  # the captured robot's own keys, attacks as it\n";
  auto line = [&](const std::string& name, const std::map<std::string, long>& m) {
    f << name << ": {";
    bool first = true;
    for (const char* reason : {"unsigned", "unknown_key", "bad_mac", "replayed", "wrong_sender"}) {
      f << (first ? "" : ", ") << reason << ": " << (m.count(reason) ? m.at(reason) : 0);
      first = false;
    }
    f << "}\n";
  };
  line("oc", oc);
  for (int a = 0; a < team; ++a) line("agent " + std::to_string(a), agent[static_cast<std::size_t>(a)]);
  std::printf("gather_attacker: %zu messages captured, %d of each attack sent -> %s\n", kept.size(), each, out.c_str());
  lcm_destroy(radio);
  lcm_destroy(replies);
  return f ? 0 : 1;
}
