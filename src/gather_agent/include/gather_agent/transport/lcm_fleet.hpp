#pragma once
// The fleet over LCM: the radio (requests, data, acks, agent states), the
// plan announcement and the lockstep clock's ticks on one LCM URL, the tick
// replies on a second one that only the OC listens to (so 20 agents do not
// each receive 20 replies a tick). The only code that sees the generated
// LCM types (lcm/*.lcm): it converts them to and from the domain structs at
// this edge, and counts and drops anything that does not decode, carries
// another schema version, names an agent outside the team or holds values
// out of range. Every message travels in a signed envelope (envelope_t,
// docs/security.md): a receiver checks its key id, MAC and counter before it
// decodes anything, and drops (counting the reason) what fails. Handlers
// only queue; nothing is decoded twice.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gather_agent/messages.hpp"
#include "gather_agent/roles/role.hpp"
#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/fleet_clock.hpp"
#include "gather_agent/transport/fleet_links.hpp"
#include "gather_agent/transport/range_gate.hpp"

typedef struct _lcm_t lcm_t;

namespace gather {
namespace agent {

class FleetEnvelopes;

// Channels.
extern const char* const kRequestChannel;  // GATHER_REQUEST
extern const char* const kDataChannel;     // GATHER_DATA
extern const char* const kAckChannel;      // GATHER_ACK
extern const char* const kStateChannel;    // GATHER_STATE
extern const char* const kPlanChannel;     // GATHER_PLAN
extern const char* const kTickChannel;     // GATHER_TICK
extern const char* const kReplyChannel;    // GATHER_REPLY
extern const char* const kTimeAskChannel;  // GATHER_TIME_ASK (agents' asks, on the replies' URL)
extern const char* const kTimeChannel;     // GATHER_TIME (the OC's answers)

enum class ClockMode : uint8_t { kLockstep = 0, kWall = 1 };

// The OC's plan announcement: what every agent must run.
struct PlanAnnounce {
  uint64_t digest = 0;
  int agents = 0;
  MissionParams params;
  double tick = 0.1;
  double loss = 0.0;
  uint64_t loss_seed = 1;
  ClockMode clock = ClockMode::kLockstep;
  double rate = 1.0;    // wall clock: mission seconds per wall second
  bool robots = false;  // the agents drive robots (lockstep: they wait for their robot's report each tick)
};

struct Tick {
  int64_t tick = 0;
  double t = 0.0;
  int32_t sent_before = 0;      // radio messages sent in tick - 1 by everyone
  int32_t commands_before = 0;  // navigation commands sent in tick - 1 by everyone (gather_world waits for them)
  bool report = false;          // replies carry custody keys
  bool done = false;            // the mission is over
  int64_t start_us = 0;         // wall clock: wall time [us since the epoch] of mission time 0
  // Per agent: how many of the sent_before messages were sent to it
  // (FleetLinks::receivers): what an agent that holds only its own links'
  // keys waits for (empty: sent_before).
  std::vector<int32_t> expect;
};

enum class ReplyStatus : uint8_t { kReady = 1, kRefused = 2, kStepped = 3 };

// Goals measured in a tick, and points of a planned path, a reply carries at
// most (tick_reply_t's MAX_MEASURED and MAX_PATH).
constexpr std::size_t kReplyMaxPoints = 256;

struct Reply {
  int64_t tick = -1;
  int16_t agent = 0;
  ReplyStatus status = ReplyStatus::kStepped;
  int32_t pid = 0;  // the agent's process id (READY replies)
  int32_t sent = 0;
  std::vector<int16_t> dests;  // each sent message's destination (header dest), in order
  int32_t commands = 0;        // navigation commands sent to its robot in this tick
  Point2 pose;
  double heading = 0.0;  // [rad]
  NavState nav_state = NavState::kIdle;
  BaseFault robot_fault = BaseFault::kNone;
  int32_t contacts = 0, robot_dropped = 0, robot_faults = 0;
  RoleKind role = RoleKind::kWorker;
  int phase = 0;
  RoleReport report;
  int32_t carried = 0, notices = 0;
  LinkCounters link;
  AuthCounters auth;  // what it dropped before decoding, by reason
  int64_t late = 0;
  int64_t incomplete = 0;     // ticks stepped without every message of the tick before
  int64_t step_us = 0;        // [us] in its control steps so far
  std::vector<int32_t> keys;  // custody keys of measured items (report ticks)
  // For views: goals measured in this tick, and the planned path (its points
  // only in the reply whose revision is new; LockstepMaster keeps them).
  std::vector<int32_t> measured_goals;
  uint32_t path_revision = 0;
  std::vector<Point2> path;
};

// The fleet's LCM URL when none is given (nor LCM_DEFAULT_URL): on one
// host, a simulation (ttl=0: no packet leaves the host), and on robots
// (gather_agent --motion lcm: ttl=1, a packet crosses one link of the
// radio network to the other robots and the OC, and no router).
inline constexpr const char* kHostFleetUrl = "udpm://239.255.76.67:7667?ttl=0";
inline constexpr const char* kRobotFleetUrl = "udpm://239.255.76.67:7667?ttl=1";

// `url`, or else LCM_DEFAULT_URL, or else `fallback`: the URL LCM opens.
std::string effective_url(const std::string& url, const char* fallback = kHostFleetUrl);

// Every counter of what the transport refused.
struct TransportCounters {
  int64_t undecodable = 0;    // does not decode as its channel's type
  int64_t wrong_version = 0;  // another schema version
  int64_t out_of_range = 0;   // an id outside the team, a count past its bound, a non-finite number
  int64_t queue_full = 0;     // arrived while the receive queue was full
  int64_t total() const { return undecodable + wrong_version + out_of_range + queue_full; }
};

// Why an agent may have heard nothing from the OC on `url` (as
// effective_url), in one clause for its last line: fleet messages that
// came but were dropped (`rejected`: another fleet key?; `refused`:
// another version?), ttl=0 on udpm (no packet leaves the host), or neither
// (the OC not running there, or multicast not routed to this computer).
std::string silence_cause(const std::string& url, const AuthCounters& rejected, const TransportCounters& refused);

class LcmFleet {
 public:
  // Opens `url` (radio, plan, ticks) and `reply_url` (replies). `listen_replies`:
  // the OC's side (subscribes to replies; agents only publish there).
  // `keys`: what every message is signed and checked with (the master, or
  // an agent's links' keys: docs/security.md); empty: insecure mode
  // (unsigned, nothing checked; the caller warns). `team`: ids
  // 0..team-1 (kMaxTeam until the plan is known). Throws
  // gather::Error("--lcm-url", ...) naming the URL when LCM cannot open it.
  // `radio`: subscribe to the fleet radio (false: gather_world, which needs
  // only the plan and the ticks).
  LcmFleet(const std::string& url, const std::string& reply_url, bool listen_replies, std::optional<KeyRing> keys,
           int team = kMaxTeam, bool radio = true);
  ~LcmFleet();
  LcmFleet(const LcmFleet&) = delete;
  LcmFleet& operator=(const LcmFleet&) = delete;

  // The team's size and, when given, which agents are collectors (one
  // entry per agent, 1: collector; the plan's roles, which a repair keeps).
  // With roles, a radio message of a kind its sender's role never sends is
  // dropped and counted as wrong sender, however well signed: requests and
  // acks come from the OC and collectors, data and states from agents.
  // `links`: who a radio message is signed for (FleetLinks::receivers;
  // unknown: a broadcast goes to the OC, or from the OC to every agent).
  void set_team(int agents, std::vector<uint8_t> collectors = {}, FleetLinks links = {});
  // Whether `sender`'s role sends messages of `kind` (set_team).
  bool may_send(int16_t sender, Kind kind) const;

  // The fleet's time (transport/fleet_clock.hpp). The OC's side answers
  // every agent's ask; every other process is on the OC's host (its clock is
  // the fleet's) until time_from_oc().
  //
  // An agent's fleet: from now on its clock is its host's (plus `skew_us`:
  // gather_agent --clock-skew, tests only), not yet synced, and keep_time()
  // measures its offset to the OC. Until the first exchange it takes nothing
  // but the OC's answers: the others' signing counters are in the fleet's
  // time, and its own clock may be seconds off.
  void time_from_oc(int16_t agent, int64_t skew_us = 0);
  // Sends an ask when one is due: every 0.25 s until 4 exchanges, then
  // every 5 s; an ask unanswered for 1 s is given up (a later answer to it
  // is refused, as is any answer that does not echo the last ask's t0).
  void keep_time();
  const FleetClock& clock() const { return clock_; }

  // Plays back recordings of the fleet's traffic (lcm-logger logs of the
  // fleet's URL and of the replies' URL) instead of listening: handle()
  // dispatches the recorded messages in time order (checked as live ones,
  // on a clock that follows the recording), and what this fleet publishes
  // goes nowhere. Throws gather::Error naming a log that does not open.
  void replay(const std::vector<std::string>& logs);
  // Every recorded message played back.
  bool replay_over() const;
  int64_t replayed() const { return replayed_; }
  // [us] the time of the last recorded message of the fleet's URL played
  // back (the radio, the plan, the clock: the OC says its start every
  // second, so a gap of seconds is the end of that recording).
  int64_t replay_end_us() const { return replay_end_us_; }

  // Publish; false (and counted) when LCM refuses.
  bool publish(const Message& m);
  bool publish(const PlanAnnounce& p);
  bool publish(const Tick& t);
  bool publish(const Reply& r);

  // Dispatches what arrived, waiting up to `timeout_ms` for something (on
  // its own sockets, or on `also_fd`: another link the caller then handles,
  // e.g. the robot's); false when nothing came.
  bool handle(int timeout_ms, int also_fd = -1);

  // What arrived, in arrival order; the caller takes and clears.
  std::vector<Message>& radio() { return radio_; }
  std::vector<Tick>& ticks() { return ticks_; }
  std::vector<Reply>& replies() { return replies_; }
  std::vector<PlanAnnounce>& plans() { return plans_; }
  const TransportCounters& refused() const { return refused_; }
  const AuthCounters& rejected() const { return auth_.counters(); }
  // Everything dropped on receipt: refused() and rejected().
  int64_t dropped() const { return refused_.total() + auth_.counters().total(); }
  bool secure() const { return auth_.secure(); }
  // It takes every message (the master's keys, or insecure), not only what
  // is sent to it (an agent's keys): then a tick's sent_before is what it
  // waits for, else the tick's expect for it.
  bool sees_all() const { return auth_.sees_all(); }
  // Messages that carried no tag for it (sent to others; not a refusal).
  int64_t not_for_me() const { return auth_.not_for_me(); }
  int64_t publish_failures() const { return publish_failures_; }
  // Its radio's LCM instance (LcmRobotLink shares it when on the same URL).
  lcm_t* radio_lcm() const { return lcm_; }
  // Its replies' LCM instance (tests: what an agent publishes there).
  lcm_t* reply_lcm() const { return reply_lcm_; }

  // The reply URL for a radio URL: the same multicast group, port + 1
  // ("udpm://239.255.76.67:7667?ttl=0" -> "...:7668?ttl=0"); other
  // providers: the same URL.
  static std::string reply_url_for(const std::string& url);

  // Handlers (called by LCM; public for the C callbacks).
  void on_radio(const char* channel, const void* data, int size);
  void on_clock(const char* channel, const void* data, int size);

 private:
  // Wraps buffer_[0, n) in an envelope from `sender`, signed for
  // receivers_, and publishes it.
  bool send(lcm_t* lcm, const char* channel, int16_t sender, int n);
  // receivers_ := who a message from `sender` to `dest` goes to.
  void address(int16_t sender, int16_t dest);
  // With a key and the plan's links: whether the envelope just opened was
  // signed for exactly those its sender and address give (address());
  // else it is counted as bad MAC (a robot's good tags for its own links on
  // a message that claims other addresses or another sender) and false.
  bool addressed_right(int16_t sender, int16_t dest);
  // The payload of a received envelope once its signature and counter are
  // good (nullptr otherwise, counted), and its signed sender.
  const uint8_t* open(const char* channel, const void* data, int size, int& payload_size, int16_t& sender);
  void on_radio_payload(const char* channel, const void* data, int size, int16_t sender);
  void on_clock_payload(const char* channel, const void* data, int size, int16_t sender);
  void on_time(const char* channel, const void* data, int size, int16_t sender);
  void not_yet(const char* channel, const void* data, int size);

  lcm_t* lcm_ = nullptr;
  lcm_t* reply_lcm_ = nullptr;
  int team_;
  std::vector<uint8_t> collectors_;  // per agent, 1: collector (empty: roles unknown)
  FleetLinks links_;                 // the plan's links (none: unknown)
  std::vector<int16_t> receivers_;   // of the message being sent
  bool listen_replies_;
  std::vector<Message> radio_;
  std::vector<Tick> ticks_;
  std::vector<Reply> replies_;
  std::vector<PlanAnnounce> plans_;
  TransportCounters refused_;
  int64_t publish_failures_ = 0;
  std::vector<uint8_t> buffer_;  // encoding: the payload
  FleetClock clock_;             // before auth_, which reads it
  int16_t time_agent_ = -1;      // time_from_oc: who asks (-1: nobody; the OC answers)
  int64_t time_asked_us_ = 0;    // t0 of the ask not yet answered (0: none)
  int64_t time_next_us_ = 0;     // local time of the next ask
  FleetAuth auth_;
  std::unique_ptr<FleetEnvelopes> envelopes_;  // sealing and opening (transport/envelope.hpp)
  struct Recording;
  std::vector<std::unique_ptr<Recording>> recordings_;  // replay(): the logs, each at its next event
  int64_t replayed_ = 0;
  int64_t replay_end_us_ = 0;
  bool replay_handle(int timeout_ms);
};

}  // namespace agent
}  // namespace gather
