// LcmFleet: the only code that sees the generated LCM types. Converts each
// message type to and from the wire, checks every field's range, and signs
// and verifies the envelope (transport/fleet_auth). Over 400 lines because it
// is one converter per message type, each next to the checks of its fields.
#include "gather_agent/transport/lcm_fleet.hpp"

#include <lcm/lcm.h>
#include <poll.h>
#include <unistd.h>

#include <gather_lcm/ack_t.hpp>
#include <gather_lcm/agent_state_t.hpp>
#include <gather_lcm/data_t.hpp>
#include <gather_lcm/plan_t.hpp>
#include <gather_lcm/request_t.hpp>
#include <gather_lcm/tick_reply_t.hpp>
#include <gather_lcm/tick_t.hpp>
#include <gather_lcm/time_sync_t.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>

#include "envelope.hpp"
#include "gather_agent/lcm_open.hpp"
#include "gather_core/error.hpp"
#include "gather_core/input_ranges.hpp"

namespace gather {
namespace agent {

const char* const kRequestChannel = "GATHER_REQUEST";
const char* const kDataChannel = "GATHER_DATA";
const char* const kAckChannel = "GATHER_ACK";
const char* const kStateChannel = "GATHER_STATE";
const char* const kPlanChannel = "GATHER_PLAN";
const char* const kTickChannel = "GATHER_TICK";
const char* const kReplyChannel = "GATHER_REPLY";
const char* const kTimeAskChannel = "GATHER_TIME_ASK";
const char* const kTimeChannel = "GATHER_TIME";

namespace {

constexpr std::size_t kRadioQueue = 4096;  // messages held between two handle() drains
constexpr std::size_t kBuffer = 32768;     // bytes: the largest encoded message (a reply with 4096 keys) fits

static_assert(gather_lcm::request_t::MAX_GOALS == kRequestPartGoals, "request part size differs from the wire type");
static_assert(gather_lcm::data_t::MAX_ITEMS == kMaxBatch, "data batch size differs from the wire type");
static_assert(gather_lcm::ack_t::MAX_KEYS == kMaxBatch, "ack batch size differs from the wire type");

bool finite(double x) { return std::isfinite(x); }

static_assert(kReplyMaxPoints == static_cast<std::size_t>(gather_lcm::tick_reply_t::MAX_MEASURED) &&
                  kReplyMaxPoints == static_cast<std::size_t>(gather_lcm::tick_reply_t::MAX_PATH),
              "Reply's bounds are tick_reply_t's");

static_assert(kBuffer <= static_cast<std::size_t>(gather_lcm::envelope_t::MAX_PAYLOAD), "a message fits an envelope");

// The wire objects decoded into (kept, so decoding allocates nothing).
struct Wire {
  gather_lcm::request_t request;
  gather_lcm::data_t data;
  gather_lcm::ack_t ack;
  gather_lcm::agent_state_t state;
  gather_lcm::plan_t plan;
  gather_lcm::tick_t tick;
  gather_lcm::tick_reply_t reply;
  gather_lcm::time_sync_t time;
};
Wire& wire() {
  static Wire w;
  return w;
}

void to_wire(const Header& h, gather_lcm::header_t& w) {
  w.schema_version = gather_lcm::header_t::SCHEMA_VERSION;
  w.sender = h.sender;
  w.dest = h.dest;
  w.seq = static_cast<int32_t>(h.seq);
  w.tick = h.tick;
  w.t = h.t;
  w.x = h.pos.x;
  w.y = h.pos.y;
  w.request = h.request;
  w.dead = static_cast<int8_t>(std::min<int>(h.dead, 2 * kMaxDead));
  w.delay = h.delay;
}

void radio_handler(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  static_cast<LcmFleet*>(user)->on_radio(channel, rbuf->data, static_cast<int>(rbuf->data_size));
}
void clock_handler(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  static_cast<LcmFleet*>(user)->on_clock(channel, rbuf->data, static_cast<int>(rbuf->data_size));
}

constexpr int64_t kQuickAskUs = 250'000;  // between asks until kQuickExchanges
constexpr int kQuickExchanges = 4;
constexpr int64_t kAskUs = 5'000'000;     // between asks after that
constexpr int64_t kGiveUpUs = 1'000'000;  // an ask unanswered this long is given up

}  // namespace

std::string effective_url(const std::string& url, const char* fallback) {
  if (!url.empty()) return url;
  const char* env = std::getenv("LCM_DEFAULT_URL");
  return env && *env ? env : fallback;
}

std::string silence_cause(const std::string& url, const AuthCounters& rejected, const TransportCounters& refused) {
  if (rejected.total() > 0)
    return "it dropped " + std::to_string(rejected.total()) + " fleet messages that failed their check (" +
           describe(rejected) + "): does it hold the OC's fleet key?";
  if (refused.total() > 0)
    return "it could not read " + std::to_string(refused.total()) +
           " fleet messages (another schema version, or out of range): is the OC the same version of gather?";
  if (url.compare(0, 7, "udpm://") != 0) return "is the OC running on this URL?";
  if (url.find("ttl=0") != std::string::npos)
    return "ttl=0 keeps LCM multicast on this computer: with the OC on another one use ttl=1 (" +
           std::string(kRobotFleetUrl) + ", docs/robots.md)";
  return "is the OC running on this URL, and does multicast reach this computer (a route for the group to the "
         "radio's interface, docs/robots.md)?";
}

std::string LcmFleet::reply_url_for(const std::string& url) {
  const std::string scheme = "udpm://";
  const std::string u = effective_url(url);
  if (u.compare(0, scheme.size(), scheme) != 0) return u;
  const std::size_t q = u.find('?', scheme.size());
  const std::string hostport = u.substr(scheme.size(), q == std::string::npos ? std::string::npos : q - scheme.size());
  const std::string rest = q == std::string::npos ? "" : u.substr(q);
  const std::size_t colon = hostport.rfind(':');
  const std::string host = colon == std::string::npos ? hostport : hostport.substr(0, colon);
  int port = 7667;
  if (colon != std::string::npos) port = std::atoi(hostport.c_str() + colon + 1);
  return scheme + host + ":" + std::to_string(port + 1) + rest;
}

LcmFleet::LcmFleet(const std::string& url, const std::string& reply_url, bool listen_replies,
                   std::optional<KeyRing> keys, int team, bool radio)
    : team_(team),
      listen_replies_(listen_replies),
      buffer_(kBuffer),
      auth_(std::move(keys), PerLinkTags{},
            {kRequestChannel, kDataChannel, kAckChannel, kStateChannel, kPlanChannel, kTickChannel, kReplyChannel,
             kTimeAskChannel, kTimeChannel},
            kMaxTeam + 1, &clock_),
      envelopes_(std::make_unique<FleetEnvelopes>(auth_, kBuffer)) {
  receivers_.reserve(kMaxTeam + 1);
  auth_.mac_only(kTimeAskChannel);
  auth_.mac_only(kTimeChannel);
  if (team < kMaxTeam) auth_.reserve(team);  // an agent learns its team from the plan (set_team)
  std::string error;
  lcm_ = open_lcm_c(url, &error);
  if (!lcm_) throw Error("--lcm-url", error);
  reply_lcm_ = open_lcm_c(reply_url, &error);
  if (!reply_lcm_) {
    lcm_destroy(lcm_);
    throw Error("--lcm-url", error + " (the tick replies' URL)");
  }
  radio_.reserve(kRadioQueue);
  if (radio)
    for (const char* ch : {kRequestChannel, kDataChannel, kAckChannel, kStateChannel})
      lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, ch, radio_handler, this), 10000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, kPlanChannel, clock_handler, this), 100);
  lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, kTickChannel, clock_handler, this), 1000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(lcm_, kTimeChannel, clock_handler, this), 1000);
  if (listen_replies) {
    lcm_subscription_set_queue_capacity(lcm_subscribe(reply_lcm_, kReplyChannel, clock_handler, this), 100000);
    lcm_subscription_set_queue_capacity(lcm_subscribe(reply_lcm_, kTimeAskChannel, clock_handler, this), 1000);
  }
}

void LcmFleet::time_from_oc(int16_t agent, int64_t skew_us) {
  clock_ = FleetClock(false, skew_us);
  auth_.start_now();
  time_agent_ = agent;
  time_asked_us_ = 0;
  time_next_us_ = 0;
}

void LcmFleet::keep_time() {
  if (time_agent_ < 0) return;
  const int64_t now = clock_.local_us();
  if (time_asked_us_ != 0 && now - time_asked_us_ < kGiveUpUs) return;  // waiting for its answer
  if (now < time_next_us_) return;
  gather_lcm::time_sync_t& w = wire().time;
  w.schema_version = gather_lcm::time_sync_t::SCHEMA_VERSION;
  w.agent = time_agent_;
  w.t0 = now, w.t1 = 0, w.t2 = 0;
  time_asked_us_ = now;
  time_next_us_ = now + (clock_.exchanges() < kQuickExchanges ? kQuickAskUs : kAskUs);
  const int n = w.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  address(time_agent_, kOc);
  if (n < 0 || !send(reply_lcm_, kTimeAskChannel, time_agent_, n)) ++publish_failures_;
}

// An lcm-logger log read event by event: a sync word, the event number and
// its time [us], the channel's and the data's lengths (big endian), then
// both. Read here, not with LCM's reader, so that a damaged log's lengths
// are checked before anything is allocated: a log ends at the first event
// that is not whole or out of bounds.
struct LcmFleet::Recording {
  static constexpr uint32_t kSync = 0xEDA1DA01;
  static constexpr uint32_t kMaxChannel = 256, kMaxData = 1 << 20;
  std::string path;
  std::FILE* file = nullptr;
  bool has_next = false;
  int64_t timestamp = 0;
  std::string channel;
  std::vector<uint8_t> data;
  static uint64_t be(const uint8_t* p, int n) {
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v = v << 8 | p[i];
    return v;
  }
  // A log ends early (one line on stderr) at an event that is not whole, out
  // of bounds, or stamped before the epoch or over an hour from the one
  // before (a damaged log: its time would stall or wrap the replay's clock).
  void stop_at(const char* why) {
    std::fprintf(stderr, "%s: the log ends at byte %ld: %s\n", path.c_str(), std::ftell(file), why);
    has_next = false;
  }
  void advance() {
    const bool had = has_next;
    has_next = false;
    uint8_t head[4 + 8 + 8 + 4 + 4];
    if (!file || std::fread(head, 1, sizeof head, file) != sizeof head) return;
    const uint32_t channel_len = static_cast<uint32_t>(be(head + 20, 4)),
                   data_len = static_cast<uint32_t>(be(head + 24, 4));
    if (be(head, 4) != kSync || channel_len == 0 || channel_len > kMaxChannel || data_len > kMaxData) return;
    timestamp = static_cast<int64_t>(be(head + 12, 8));
    channel.resize(channel_len);
    data.resize(data_len);
    if (std::fread(channel.data(), 1, channel_len, file) != channel_len ||
        std::fread(data.data(), 1, data_len, file) != data_len)
      return had ? stop_at("an event cut short") : void();
    has_next = true;
  }
  ~Recording() {
    if (file) std::fclose(file);
  }
};

void LcmFleet::replay(const std::vector<std::string>& logs) {
  std::optional<int64_t> first;
  for (const std::string& path : logs) {
    auto r = std::make_unique<Recording>();
    r->path = path;
    r->file = std::fopen(path.c_str(), "rb");
    if (!r->file) throw Error(path, std::string("cannot read this LCM log: ") + std::strerror(errno));
    r->advance();
    if (!r->has_next) throw Error(path, "not an LCM log (lcm-logger's format), or empty");
    if (!first || r->timestamp < *first) first = r->timestamp;
    recordings_.push_back(std::move(r));
  }
  clock_ = FleetClock(true);
  clock_.set_virtual(*first);
  auth_.start_now();  // counters are judged on the recording's time
}

bool LcmFleet::replay_over() const {
  for (const auto& r : recordings_)
    if (r->has_next) return false;
  return true;
}

bool LcmFleet::replay_handle(int timeout_ms) {
  const int64_t until = clock_.local_us() + std::max(timeout_ms, 1) * 1000;
  bool any = false;
  for (;;) {
    Recording* soonest = nullptr;
    for (const auto& r : recordings_)
      if (r->has_next && r->timestamp <= until && (!soonest || r->timestamp < soonest->timestamp)) soonest = r.get();
    if (!soonest) break;
    clock_.set_virtual(std::max(clock_.local_us(), soonest->timestamp));
    const char* ch = soonest->channel.c_str();
    const int n = static_cast<int>(soonest->data.size());
    const bool radio = std::strcmp(ch, kRequestChannel) == 0 || std::strcmp(ch, kDataChannel) == 0 ||
                       std::strcmp(ch, kAckChannel) == 0 || std::strcmp(ch, kStateChannel) == 0;
    const bool clock = std::strcmp(ch, kPlanChannel) == 0 || std::strcmp(ch, kTickChannel) == 0;
    if (radio)
      on_radio(ch, soonest->data.data(), n);
    else if (clock || (std::strcmp(ch, kReplyChannel) == 0 && listen_replies_))
      on_clock(ch, soonest->data.data(), n);
    if (radio || clock) replay_end_us_ = soonest->timestamp;
    ++replayed_, any = true;
    soonest->advance();
  }
  clock_.set_virtual(until);
  return any;
}

LcmFleet::~LcmFleet() {
  if (lcm_) lcm_destroy(lcm_);
  if (reply_lcm_) lcm_destroy(reply_lcm_);
}

bool LcmFleet::publish(const Message& m) {
  Wire& w = wire();
  int n = -1;
  const char* channel = nullptr;
  switch (m.h.kind) {
    case Kind::kRequest: {
      gather_lcm::request_t& r = w.request;
      to_wire(m.h, r.h);
      r.request = m.request.request;
      r.issued_at = m.request.issued_at;
      r.first_goal = m.request.first_goal;
      r.total = m.request.total;
      r.part = static_cast<int16_t>(m.request.part);
      r.parts = static_cast<int16_t>(m.request.parts);
      r.count = static_cast<int16_t>(m.request.count);
      for (int i = 0; i < kRequestPartGoals; ++i)
        r.cells[i] = i < m.request.count ? static_cast<int32_t>(m.request.cells[i]) : 0;
      r.n_dead = static_cast<int8_t>(std::min<int>(m.request.dead_count, kMaxDead));
      r.dead.assign(m.request.dead, m.request.dead + r.n_dead);
      r.dead_revoked = static_cast<int32_t>(m.request.dead_revoked);
      n = r.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
      channel = kRequestChannel;
      break;
    }
    case Kind::kData: {
      gather_lcm::data_t& d = w.data;
      to_wire(m.h, d.h);
      d.count = static_cast<int16_t>(m.data.count);
      for (int i = 0; i < kMaxBatch; ++i) {
        gather_lcm::data_item_t& o = d.items[i];
        if (i < m.data.count) {
          const DataItem& it = m.data.items[i];
          o.key = it.key, o.kind = static_cast<int8_t>(it.kind), o.by = it.by, o.at = it.at;
          o.picked_up_by = it.picked_up_by, o.picked_up_at = it.picked_up_at;
          o.deadline = it.deadline;
        } else {
          o = gather_lcm::data_item_t{};
        }
      }
      n = d.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
      channel = kDataChannel;
      break;
    }
    case Kind::kAck: {
      gather_lcm::ack_t& a = w.ack;
      to_wire(m.h, a.h);
      a.count = static_cast<int16_t>(m.ack.count);
      for (int i = 0; i < kMaxBatch; ++i) a.keys[i] = i < m.ack.count ? m.ack.keys[i] : 0;
      n = a.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
      channel = kAckChannel;
      break;
    }
    case Kind::kState: {
      gather_lcm::agent_state_t& s = w.state;
      to_wire(m.h, s.h);
      s.role = static_cast<int8_t>(m.state.role);
      s.carried = static_cast<int16_t>(std::min<int>(m.state.carried, 32767));
      s.notices = static_cast<int16_t>(std::min<int>(m.state.notices, 32767));
      s.pending = static_cast<int16_t>(std::min<int>(m.state.pending, 32767));
      s.measured = m.state.measured;
      s.back_by = m.state.back_by;
      s.n_heard = static_cast<int16_t>(std::min<int>(m.state.heard_count, kMaxHeard));
      s.heard_agent.assign(m.state.heard_agent, m.state.heard_agent + s.n_heard);
      s.heard_at.assign(m.state.heard_at, m.state.heard_at + s.n_heard);
      n = s.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
      channel = kStateChannel;
      break;
    }
  }
  address(m.h.sender, m.h.dest);
  if (n < 0 || !send(lcm_, channel, m.h.sender, n)) return ++publish_failures_, false;
  return true;
}

bool LcmFleet::publish(const PlanAnnounce& p) {
  gather_lcm::plan_t& w = wire().plan;
  w.schema_version = gather_lcm::plan_t::SCHEMA_VERSION;
  w.digest = static_cast<int64_t>(p.digest);
  w.agents = p.agents;
  w.cycles = p.params.cycles;
  w.seed = static_cast<int32_t>(p.params.seed);
  w.goals_per_request = p.params.goals_per_request;
  w.data_capacity = static_cast<int32_t>(p.params.data_capacity);
  w.notice_capacity = static_cast<int32_t>(p.params.notice_capacity);
  w.beacon_period = p.params.beacon_period;
  w.resend_after = p.params.resend_after;
  w.tick = p.tick;
  w.loss = p.loss;
  w.loss_seed = static_cast<int64_t>(p.loss_seed);
  w.clock = static_cast<int8_t>(p.clock);
  w.rate = p.rate;
  w.repair = static_cast<int8_t>(p.params.repair);
  w.silent_intervals = p.params.silent_intervals;
  w.ask_after = p.params.ask_after;
  w.link_step_m = p.params.protocol.link_step_m;
  w.window_margin_m = p.params.protocol.window_margin_m;
  w.two_opt_rounds = p.params.protocol.two_opt_rounds;
  w.replan_guard_s = p.params.protocol.replan_guard_s;
  w.wait_loops = p.params.protocol.wait_loops;
  w.place_tolerance_m = p.params.protocol.place_tolerance_m;
  w.home_clearance_m = p.params.protocol.home_clearance_m;
  w.robots = p.robots;
  const int n = w.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  address(kOc, kBroadcast);
  if (n < 0 || !send(lcm_, kPlanChannel, kOc, n)) return ++publish_failures_, false;
  return true;
}

bool LcmFleet::publish(const Tick& t) {
  gather_lcm::tick_t& w = wire().tick;
  w.schema_version = gather_lcm::tick_t::SCHEMA_VERSION;
  w.tick = t.tick;
  w.t = t.t;
  w.sent_before = t.sent_before;
  w.commands_before = t.commands_before;
  w.report = t.report;
  w.done = t.done;
  w.start_us = t.start_us;
  w.n_expect = static_cast<int16_t>(std::min<std::size_t>(t.expect.size(), gather_lcm::tick_t::MAX_AGENTS));
  w.expect.assign(t.expect.begin(), t.expect.begin() + w.n_expect);
  const int n = w.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  address(kOc, kBroadcast);
  if (n < 0 || !send(lcm_, kTickChannel, kOc, n)) return ++publish_failures_, false;
  return true;
}

bool LcmFleet::publish(const Reply& r) {
  gather_lcm::tick_reply_t& w = wire().reply;
  w.schema_version = gather_lcm::tick_reply_t::SCHEMA_VERSION;
  w.tick = r.tick;
  w.agent = r.agent;
  w.status = static_cast<int8_t>(r.status);
  w.pid = r.pid;
  w.sent = r.sent;
  w.n_dests = static_cast<int16_t>(std::min<std::size_t>(r.dests.size(), gather_lcm::tick_reply_t::MAX_DESTS));
  w.dests.assign(r.dests.begin(), r.dests.begin() + w.n_dests);
  w.commands = r.commands;
  w.x = r.pose.x;
  w.y = r.pose.y;
  w.heading = r.heading;
  w.nav_state = static_cast<int8_t>(r.nav_state);
  w.robot_fault = static_cast<int8_t>(r.robot_fault);
  w.legs = static_cast<int32_t>(r.report.legs);
  w.legs_late = static_cast<int32_t>(r.report.legs_late);
  w.late_median_s = r.report.late_median_s;
  w.late_max_s = r.report.late_max_s;
  w.nav_failures = static_cast<int32_t>(r.report.nav_failures);
  w.unreachable = static_cast<int32_t>(r.report.unreachable);
  w.contacts = r.contacts;
  w.robot_dropped = r.robot_dropped;
  w.robot_faults = r.robot_faults;
  w.loops = static_cast<int32_t>(r.report.loops);
  w.loop_late_median_s = r.report.loop_late_median_s;
  w.loop_late_max_s = r.report.loop_late_max_s;
  w.role = static_cast<int8_t>(r.role);
  w.phase = static_cast<int8_t>(r.phase);
  w.measured = static_cast<int32_t>(r.report.measured);
  w.expired = static_cast<int32_t>(r.report.expired);
  w.skipped = static_cast<int32_t>(r.report.skipped);
  w.dropped = static_cast<int32_t>(r.report.dropped);
  w.carried = r.carried;
  w.notices = r.notices;
  w.pending = static_cast<int32_t>(r.report.pending);
  w.request = static_cast<int32_t>(r.report.requests);
  w.refused_full = static_cast<int32_t>(r.report.refused_full);
  w.lost_notices = static_cast<int32_t>(r.report.lost_notices);
  w.refused_revoked = r.report.refused_revoked;
  w.link_sent = r.link.sent;
  w.link_received = r.link.received;
  w.link_gated = r.link.gated;
  w.link_lost = r.link.lost;
  w.link_bad = r.link.bad;
  w.link_overflow = r.link.overflow;
  w.rejected_unsigned = r.auth.unsigned_msgs;
  w.rejected_unknown_key = r.auth.unknown_key;
  w.rejected_bad_mac = r.auth.bad_mac;
  w.rejected_replayed = r.auth.replayed;
  w.rejected_wrong_sender = r.auth.wrong_sender;
  w.late = r.late;
  w.incomplete = r.incomplete;
  w.step_us = r.step_us;
  const std::size_t keys = std::min<std::size_t>(r.keys.size(), gather_lcm::tick_reply_t::MAX_KEYS);
  w.n_keys = static_cast<int16_t>(keys);
  w.keys.assign(r.keys.begin(), r.keys.begin() + static_cast<long>(keys));
  const std::size_t measured = std::min<std::size_t>(r.measured_goals.size(), gather_lcm::tick_reply_t::MAX_MEASURED);
  w.n_measured = static_cast<int16_t>(measured);
  w.measured_goals.assign(r.measured_goals.begin(), r.measured_goals.begin() + static_cast<long>(measured));
  w.path_revision = static_cast<int32_t>(r.path_revision);
  const std::size_t points = std::min<std::size_t>(r.path.size(), gather_lcm::tick_reply_t::MAX_PATH);
  w.n_path = static_cast<int16_t>(points);
  w.path_x.resize(points);
  w.path_y.resize(points);
  for (std::size_t i = 0; i < points; ++i) {
    w.path_x[i] = static_cast<float>(r.path[i].x);
    w.path_y[i] = static_cast<float>(r.path[i].y);
  }
  const int n = w.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
  address(r.agent, kOc);
  if (n < 0 || !send(reply_lcm_, kReplyChannel, r.agent, n)) return ++publish_failures_, false;
  return true;
}

void LcmFleet::address(int16_t sender, int16_t dest) {
  receivers_.clear();
  if (!auth_.secure()) return;  // insecure: no tags, and everyone takes everything
  if (links_.agents() == team_ && team_ > 0) return links_.receivers(sender, dest, receivers_);
  // The plan's links not known (yet): the OC's broadcasts go to every agent,
  // everything else to the OC or to whom it is addressed.
  if (dest != kBroadcast)
    receivers_.push_back(dest);
  else if (sender != kOc)
    receivers_.push_back(kOc);
  else
    for (int a = 0; a < team_; ++a) receivers_.push_back(static_cast<int16_t>(a));
}

bool LcmFleet::addressed_right(int16_t sender, int16_t dest) {
  if (!auth_.secure() || links_.agents() != team_ || team_ <= 0) return true;
  address(sender, dest);
  if (envelopes_->receivers() == receivers_) return true;
  auth_.count_bad_mac();  // its tags are good, but for others than its addresses say
  return false;
}

bool LcmFleet::send(lcm_t* lcm, const char* channel, int16_t sender, int n) {
  const int m = envelopes_->seal(channel, sender, buffer_.data(), n, receivers_.data(), receivers_.size());
  if (!recordings_.empty()) return m >= 0;  // a replay: nobody to hear it (memq would keep it)
  return m >= 0 && lcm_publish(lcm, channel, envelopes_->bytes(), static_cast<unsigned>(m)) == 0;
}

bool LcmFleet::handle(int timeout_ms, int also_fd) {
  if (!recordings_.empty()) return replay_handle(timeout_ms);
  // An agent never asks for the replies' file descriptor: with LCM's udpm
  // that would join the replies' group, and every agent would receive every
  // other agent's replies.
  pollfd fds[3] = {{lcm_get_fileno(lcm_), POLLIN, 0},
                   {listen_replies_ ? lcm_get_fileno(reply_lcm_) : -1, POLLIN, 0},
                   {also_fd, POLLIN, 0}};
  const nfds_t n = listen_replies_ ? 2 : 1;
  if (also_fd >= 0) {
    pollfd all[3] = {fds[0], fds[1], fds[2]};
    if (::poll(all, 3, timeout_ms) <= 0) return false;
    if (::poll(fds, n, 0) <= 0) return true;  // only the other link: the caller handles it
  } else if (::poll(fds, n, timeout_ms) <= 0) {
    return false;
  }
  // Drain everything that is there without blocking again.
  for (int round = 0; round < 1000; ++round) {
    bool any = false;
    if (fds[0].revents & POLLIN) lcm_handle(lcm_), any = true;
    if (n > 1 && (fds[1].revents & POLLIN)) lcm_handle(reply_lcm_), any = true;
    if (!any || ::poll(fds, n, 0) <= 0) break;
  }
  return true;
}

const uint8_t* LcmFleet::open(const char* channel, const void* data, int size, int& payload_size, int16_t& sender) {
  switch (envelopes_->open(channel, data, size)) {
    case FleetEnvelopes::Opened::kOk:
      payload_size = envelopes_->payload_size();
      sender = envelopes_->sender();
      return envelopes_->payload();
    case FleetEnvelopes::Opened::kUndecodable: ++refused_.undecodable; break;
    case FleetEnvelopes::Opened::kOutOfRange: ++refused_.out_of_range; break;
    case FleetEnvelopes::Opened::kWrongVersion: ++refused_.wrong_version; break;
    case FleetEnvelopes::Opened::kRejected: break;  // counted by FleetAuth
    case FleetEnvelopes::Opened::kNotForMe: break;  // sent to others (counted by FleetAuth)
  }
  return nullptr;
}

void LcmFleet::on_radio(const char* channel, const void* data, int size) {
  if (!clock_.synced()) return not_yet(channel, data, size);
  int n = 0;
  int16_t sender = 0;
  if (const uint8_t* p = open(channel, data, size, n, sender)) on_radio_payload(channel, p, n, sender);
}

void LcmFleet::on_clock(const char* channel, const void* data, int size) {
  const bool time = std::strcmp(channel, kTimeChannel) == 0 || std::strcmp(channel, kTimeAskChannel) == 0;
  if (!clock_.synced() && !time) return not_yet(channel, data, size);
  int n = 0;
  int16_t sender = 0;
  const uint8_t* p = open(channel, data, size, n, sender);
  if (p && time)
    on_time(channel, p, n, sender);
  else if (p)
    on_clock_payload(channel, p, n, sender);
}

void LcmFleet::not_yet(const char* channel, const void* data, int size) {
  // Before its first clock exchange an agent cannot judge counters (they are
  // on the fleet's time): it checks the key and MAC only, so that traffic
  // under another key is counted (silence_cause names it), and takes nothing.
  envelopes_->open(channel, data, size, /*counters=*/false);
}

void LcmFleet::on_time(const char* channel, const void* data, int size, int16_t sender) {
  const int64_t received = clock_.local_us();
  gather_lcm::time_sync_t& w = wire().time;
  if (safe_decode(w, data, size) != size) return void(++refused_.undecodable);
  if (w.schema_version != gather_lcm::time_sync_t::SCHEMA_VERSION) return void(++refused_.wrong_version);
  if (w.agent < 0 || w.agent >= team_ || w.t0 <= 0 || w.t1 < 0 || w.t2 < w.t1) return void(++refused_.out_of_range);
  const bool ask = std::strcmp(channel, kTimeAskChannel) == 0;
  if (ask ? !addressed_right(sender, kOc) : !addressed_right(kOc, w.agent)) return;
  if (ask) {  // the OC: answer at once
    if (!listen_replies_ || time_agent_ >= 0) return;
    if (w.agent != sender) return auth_.count_wrong_sender();
    w.t1 = received + clock_.offset_us();
    w.t2 = clock_.now_us();
    const int n = w.encode(buffer_.data(), 0, static_cast<int>(buffer_.size()));
    address(kOc, w.agent);
    if (n < 0 || !send(lcm_, kTimeChannel, kOc, n)) ++publish_failures_;
    return;
  }
  if (sender != kOc) return auth_.count_wrong_sender();
  // An agent: only the answer to its own last ask, once.
  if (w.agent != time_agent_ || w.t0 != time_asked_us_) return;
  time_asked_us_ = 0;
  clock_.add(w.t0, w.t1, w.t2, received);
}

void LcmFleet::on_radio_payload(const char* channel, const void* data, int size, int16_t sender) {
  Wire& w = wire();
  Message m;
  const gather_lcm::header_t* h = nullptr;
  auto decoded = [&](int n) {
    if (n != size) return ++refused_.undecodable, false;
    return true;
  };
  if (std::strcmp(channel, kRequestChannel) == 0) {
    if (!decoded(safe_decode(w.request, data, size))) return;
    const gather_lcm::request_t& r = w.request;
    h = &r.h;
    if (r.count < 0 || r.count > kRequestPartGoals || r.parts < 1 || r.parts > kMaxRequestParts || r.part < 0 ||
        r.part >= r.parts || r.request < 0 || r.total < 0 || r.total > kMaxRequestParts * kRequestPartGoals ||
        r.first_goal < 0 || r.first_goal > std::numeric_limits<int32_t>::max() - r.total || !finite(r.issued_at))
      return void(++refused_.out_of_range);
    m.h.kind = Kind::kRequest;
    m.request.request = r.request;
    m.request.issued_at = r.issued_at;
    m.request.first_goal = r.first_goal;
    m.request.total = r.total;
    m.request.part = static_cast<uint16_t>(r.part);
    m.request.parts = static_cast<uint16_t>(r.parts);
    m.request.count = static_cast<uint16_t>(r.count);
    for (int i = 0; i < r.count; ++i) {
      if (r.cells[i] < 0) return void(++refused_.out_of_range);
      m.request.cells[i] = static_cast<uint32_t>(r.cells[i]);
    }
    if (r.n_dead < 0 || r.n_dead > kMaxDead) return void(++refused_.out_of_range);
    m.request.dead_count = static_cast<uint8_t>(r.n_dead);
    for (int i = 0; i < r.n_dead; ++i) {
      if (r.dead[static_cast<std::size_t>(i)] < 0 || r.dead[static_cast<std::size_t>(i)] >= team_)
        return void(++refused_.out_of_range);
      m.request.dead[i] = r.dead[static_cast<std::size_t>(i)];
    }
    // A bit for each declaration it lists, none beyond.
    const uint32_t revoked = static_cast<uint32_t>(r.dead_revoked);
    if (r.n_dead < 32 && (revoked >> r.n_dead) != 0) return void(++refused_.out_of_range);
    m.request.dead_revoked = revoked;
  } else if (std::strcmp(channel, kDataChannel) == 0) {
    if (!decoded(safe_decode(w.data, data, size))) return;
    const gather_lcm::data_t& d = w.data;
    h = &d.h;
    if (d.count < 0 || d.count > kMaxBatch) return void(++refused_.out_of_range);
    m.h.kind = Kind::kData;
    m.data.count = static_cast<uint16_t>(d.count);
    for (int i = 0; i < d.count; ++i) {
      const gather_lcm::data_item_t& o = d.items[i];
      if (o.kind < 1 || o.kind > 5 || !finite(o.at) || !finite(o.picked_up_at) || std::isnan(o.deadline) || o.by < 0 ||
          o.by >= team_ || o.picked_up_by < -1 || o.picked_up_by >= team_)
        return void(++refused_.out_of_range);
      DataItem& it = m.data.items[i];
      it.key = o.key, it.kind = static_cast<ItemKind>(o.kind), it.by = o.by, it.at = o.at;
      it.picked_up_by = o.picked_up_by, it.picked_up_at = o.picked_up_at;
      it.deadline = o.deadline;
    }
  } else if (std::strcmp(channel, kAckChannel) == 0) {
    if (!decoded(safe_decode(w.ack, data, size))) return;
    const gather_lcm::ack_t& a = w.ack;
    h = &a.h;
    if (a.count < 0 || a.count > kMaxBatch) return void(++refused_.out_of_range);
    m.h.kind = Kind::kAck;
    m.ack.count = static_cast<uint16_t>(a.count);
    std::copy(a.keys, a.keys + a.count, m.ack.keys);
  } else if (std::strcmp(channel, kStateChannel) == 0) {
    if (!decoded(safe_decode(w.state, data, size))) return;
    const gather_lcm::agent_state_t& s = w.state;
    h = &s.h;
    if (s.role < 1 || s.role > 3 || s.carried < 0 || s.notices < 0 || s.pending < 0 ||
        !(s.back_by >= 0 && s.back_by <= 1e9))
      return void(++refused_.out_of_range);
    m.h.kind = Kind::kState;
    m.state.role = static_cast<RoleKind>(s.role);
    m.state.carried = static_cast<uint16_t>(s.carried);
    m.state.notices = static_cast<uint16_t>(s.notices);
    m.state.pending = static_cast<uint16_t>(s.pending);
    m.state.measured = s.measured;
    m.state.back_by = s.back_by;
    if (s.n_heard < 0 || s.n_heard > kMaxHeard) return void(++refused_.out_of_range);
    m.state.heard_count = static_cast<uint8_t>(s.n_heard);
    for (int i = 0; i < s.n_heard; ++i) {
      const int16_t a = s.heard_agent[static_cast<std::size_t>(i)];
      const double at = s.heard_at[static_cast<std::size_t>(i)];
      if (a < 0 || a >= team_ || !finite(at)) return void(++refused_.out_of_range);
      m.state.heard_agent[i] = a, m.state.heard_at[i] = at;
    }
  } else {
    return;
  }
  if (h->schema_version != gather_lcm::header_t::SCHEMA_VERSION) return void(++refused_.wrong_version);
  if (h->sender != sender) return auth_.count_wrong_sender();
  if (!addressed_right(sender, h->dest)) return;
  if (!may_send(sender, m.h.kind)) return auth_.count_wrong_sender();  // not its role's to send
  if (h->sender < kOc || h->sender >= team_ || (h->dest != kBroadcast && (h->dest < kOc || h->dest >= team_)) ||
      h->seq < 0 || h->request < -1 || h->dead < 0 || h->dead > 2 * kMaxDead || !finite(h->t) || !finite(h->x) ||
      !finite(h->y) || !(std::abs(h->delay) <= kMaxDelay))
    return void(++refused_.out_of_range);
  m.h.sender = h->sender;
  m.h.dest = h->dest;
  m.h.seq = static_cast<uint32_t>(h->seq);
  m.h.tick = h->tick;
  m.h.t = h->t;
  m.h.pos = Point2{h->x, h->y};
  m.h.request = h->request;
  m.h.dead = static_cast<uint8_t>(h->dead);
  m.h.delay = h->delay;
  if (radio_.size() >= radio_.capacity()) return void(++refused_.queue_full);
  radio_.push_back(m);
}

void LcmFleet::set_team(int agents, std::vector<uint8_t> collectors, FleetLinks links) {
  if (!collectors.empty() && collectors.size() != static_cast<std::size_t>(agents))
    throw RuntimeError("LcmFleet::set_team", "one role per agent");
  if (links.agents() != 0 && links.agents() != agents) throw RuntimeError("LcmFleet::set_team", "one link per agent");
  team_ = agents;
  collectors_ = std::move(collectors);
  links_ = std::move(links);
  if (links_.agents() == agents) auth_.set_links(links_);  // the master: the plan's links, and no other
  auth_.reserve(agents);
}

bool LcmFleet::may_send(int16_t sender, Kind kind) const {
  const bool from_oc = kind == Kind::kRequest || kind == Kind::kAck;  // the OC's, or a collector's to its workers
  if (sender == kOc) return from_oc;
  if (sender < 0 || static_cast<std::size_t>(sender) >= collectors_.size()) return true;  // roles unknown
  return !from_oc || collectors_[static_cast<std::size_t>(sender)] != 0;
}

void LcmFleet::on_clock_payload(const char* channel, const void* data, int size, int16_t sender) {
  Wire& w = wire();
  // Ticks and plans come from the OC, a reply from its agent.
  if (std::strcmp(channel, kReplyChannel) != 0 && sender != kOc) return auth_.count_wrong_sender();
  // Ticks and plans to every agent, a reply to the OC.
  if (std::strcmp(channel, kReplyChannel) == 0 ? !addressed_right(sender, kOc) : !addressed_right(kOc, kBroadcast))
    return;
  if (std::strcmp(channel, kTickChannel) == 0) {
    w.tick.expect.clear();  // the decoder leaves an array of 0 as it was
    if (safe_decode(w.tick, data, size) != size) return void(++refused_.undecodable);
    if (w.tick.schema_version != gather_lcm::tick_t::SCHEMA_VERSION) return void(++refused_.wrong_version);
    if (w.tick.tick < 0 || !finite(w.tick.t) || w.tick.sent_before < 0 || w.tick.commands_before < 0 ||
        w.tick.start_us < 0 || w.tick.n_expect < 0 || w.tick.n_expect > gather_lcm::tick_t::MAX_AGENTS ||
        std::any_of(w.tick.expect.begin(), w.tick.expect.end(),
                    [&](int32_t e) { return e < 0 || e > w.tick.sent_before; }))
      return void(++refused_.out_of_range);
    Tick t;
    t.tick = w.tick.tick, t.t = w.tick.t, t.sent_before = w.tick.sent_before;
    t.commands_before = w.tick.commands_before;
    t.report = w.tick.report != 0, t.done = w.tick.done != 0, t.start_us = w.tick.start_us;
    t.expect.assign(w.tick.expect.begin(), w.tick.expect.end());
    ticks_.push_back(t);
  } else if (std::strcmp(channel, kPlanChannel) == 0) {
    if (safe_decode(w.plan, data, size) != size) return void(++refused_.undecodable);
    const gather_lcm::plan_t& p = w.plan;
    if (p.schema_version != gather_lcm::plan_t::SCHEMA_VERSION) return void(++refused_.wrong_version);
    // Bounded as the scenario's own values are (docs/input_limits.md): a
    // plan message sizes the agents' buffers.
    constexpr int32_t kMaxCapacity = 1 << 22;
    if (p.agents < 1 || p.agents > kMaxTeam || p.cycles < 1 || p.cycles > kMaxRequests || p.goals_per_request < 0 ||
        p.goals_per_request > input_range(range::kGoalsPerRequest).hi || p.data_capacity < 1 ||
        p.data_capacity > kMaxCapacity || p.notice_capacity < 1 || p.notice_capacity > kMaxCapacity ||
        !(p.tick > 0 && p.tick <= 0.1) || !(p.loss >= 0 && p.loss < 1) ||
        !(p.beacon_period > 0 && p.beacon_period <= 3600) || !(p.resend_after > 0 && p.resend_after <= 3600) ||
        (p.clock != 0 && p.clock != 1) || !(p.rate > 0 && p.rate <= 1e6) || (p.repair != 0 && p.repair != 1) ||
        !(p.silent_intervals >= 1.5 && p.silent_intervals <= 100.0) || !(p.ask_after >= 0 && p.ask_after <= 60))
      return void(++refused_.out_of_range);
    mission::ProtocolParams protocol;
    protocol.link_step_m = p.link_step_m, protocol.window_margin_m = p.window_margin_m;
    protocol.two_opt_rounds = p.two_opt_rounds;
    protocol.replan_guard_s = p.replan_guard_s, protocol.wait_loops = p.wait_loops;
    protocol.place_tolerance_m = p.place_tolerance_m, protocol.home_clearance_m = p.home_clearance_m;
    try {
      mission::check_params(protocol);  // the protocol's own ranges
    } catch (const Error&) {
      return void(++refused_.out_of_range);
    }
    PlanAnnounce a;
    a.digest = static_cast<uint64_t>(p.digest);
    a.agents = p.agents;
    a.params.cycles = p.cycles;
    a.params.seed = static_cast<unsigned>(p.seed);
    a.params.goals_per_request = p.goals_per_request;
    a.params.data_capacity = static_cast<std::size_t>(p.data_capacity);
    a.params.notice_capacity = static_cast<std::size_t>(p.notice_capacity);
    a.params.beacon_period = p.beacon_period;
    a.params.resend_after = p.resend_after;
    a.params.repair = static_cast<mission::RepairMode>(p.repair);
    a.params.silent_intervals = p.silent_intervals;
    a.params.ask_after = p.ask_after;
    a.params.protocol = protocol;
    a.tick = p.tick;
    a.loss = p.loss;
    a.loss_seed = static_cast<uint64_t>(p.loss_seed);
    a.clock = static_cast<ClockMode>(p.clock);
    a.rate = p.rate;
    a.robots = p.robots;
    plans_.push_back(a);
  } else if (std::strcmp(channel, kReplyChannel) == 0) {
    w.reply.dests.clear();  // the decoder leaves an array of 0 as it was
    if (safe_decode(w.reply, data, size) != size) return void(++refused_.undecodable);
    const gather_lcm::tick_reply_t& r = w.reply;
    if (r.schema_version != gather_lcm::tick_reply_t::SCHEMA_VERSION) return void(++refused_.wrong_version);
    if (r.agent < 0 || r.agent >= team_ || r.status < 1 || r.status > 3 || r.sent < 0 || r.n_keys < 0 ||
        r.n_keys > gather_lcm::tick_reply_t::MAX_KEYS || !finite(r.x) || !finite(r.y) || r.n_measured < 0 ||
        r.n_measured > gather_lcm::tick_reply_t::MAX_MEASURED || r.n_path < 0 ||
        r.n_path > gather_lcm::tick_reply_t::MAX_PATH || r.commands < 0 || !finite(r.heading) || r.nav_state < 0 ||
        r.nav_state > 4 || r.robot_fault < 0 || r.robot_fault > 3 || !finite(r.late_median_s) ||
        !finite(r.late_max_s) || !finite(r.loop_late_median_s) || !finite(r.loop_late_max_s) || r.n_dests != r.sent ||
        std::any_of(r.dests.begin(), r.dests.end(), [&](int16_t d) { return d < kBroadcast || d >= team_; }))
      return void(++refused_.out_of_range);
    if (r.agent != sender) return auth_.count_wrong_sender();
    for (int i = 0; i < r.n_measured; ++i)
      if (r.measured_goals[static_cast<std::size_t>(i)] < 0) return void(++refused_.out_of_range);
    for (int i = 0; i < r.n_path; ++i)
      if (!std::isfinite(r.path_x[static_cast<std::size_t>(i)]) ||
          !std::isfinite(r.path_y[static_cast<std::size_t>(i)]))
        return void(++refused_.out_of_range);
    Reply o;
    o.tick = r.tick;
    o.agent = r.agent;
    o.status = static_cast<ReplyStatus>(r.status);
    o.pid = r.pid;
    o.sent = r.sent;
    o.dests.assign(r.dests.begin(), r.dests.end());
    o.commands = r.commands;
    o.pose = Point2{r.x, r.y};
    o.heading = r.heading;
    o.nav_state = static_cast<NavState>(r.nav_state);
    o.robot_fault = static_cast<BaseFault>(r.robot_fault);
    o.contacts = r.contacts, o.robot_dropped = r.robot_dropped, o.robot_faults = r.robot_faults;
    o.report.legs = r.legs, o.report.legs_late = r.legs_late;
    o.report.late_median_s = r.late_median_s, o.report.late_max_s = r.late_max_s;
    o.report.nav_failures = r.nav_failures, o.report.unreachable = r.unreachable;
    o.report.loops = r.loops, o.report.loop_late_median_s = r.loop_late_median_s;
    o.report.loop_late_max_s = r.loop_late_max_s;
    o.role = static_cast<RoleKind>(r.role);
    o.phase = r.phase;
    o.report.role = o.role;
    o.report.id = r.agent;
    o.report.measured = r.measured, o.report.expired = r.expired, o.report.skipped = r.skipped;
    o.report.dropped = r.dropped, o.report.pending = r.pending, o.report.requests = r.request;
    o.report.refused_full = r.refused_full, o.report.lost_notices = r.lost_notices;
    o.report.refused_revoked = r.refused_revoked;
    o.carried = r.carried, o.notices = r.notices;
    o.link.sent = r.link_sent, o.link.received = r.link_received, o.link.gated = r.link_gated;
    o.link.lost = r.link_lost, o.link.bad = r.link_bad, o.link.overflow = r.link_overflow;
    o.auth.unsigned_msgs = r.rejected_unsigned, o.auth.unknown_key = r.rejected_unknown_key;
    o.auth.bad_mac = r.rejected_bad_mac, o.auth.replayed = r.rejected_replayed;
    o.auth.wrong_sender = r.rejected_wrong_sender;
    o.late = r.late;
    o.incomplete = r.incomplete;
    o.step_us = r.step_us;
    // The decoder reuses its arrays and resizes them only for a non-zero
    // count: take exactly the counted elements.
    o.keys.assign(r.keys.begin(), r.keys.begin() + r.n_keys);
    o.measured_goals.assign(r.measured_goals.begin(), r.measured_goals.begin() + r.n_measured);
    o.path_revision = static_cast<uint32_t>(r.path_revision);
    o.path.resize(static_cast<std::size_t>(r.n_path));
    for (std::size_t i = 0; i < o.path.size(); ++i) o.path[i] = Point2{r.path_x[i], r.path_y[i]};
    replies_.push_back(std::move(o));
  }
}

}  // namespace agent
}  // namespace gather
