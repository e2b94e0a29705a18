#pragma once
// Fleet radio messages as the roles see them: plain, fixed-size structs
// with bounded arrays, no wire format. Their wire form is the LCM types in
// lcm/*.lcm; only transport/lcm_bus converts between the two (the roles never
// see LCM). Every message carries its sender, the sender's position when it
// sent it (the range gate decides with it) and the newest request the sender
// knows (so a receiver with a newer one can pass it on).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace agent {

constexpr int16_t kOc = -1;         // agent id of the Operation Center
constexpr int16_t kBroadcast = -2;  // destination: whoever hears it
constexpr int kMaxTeam = 4096;      // agent ids 0..kMaxTeam-1

constexpr int kRequestPartGoals = 256;  // goals in one request message (a request is sent in parts)
constexpr int kMaxRequestParts = 64;    // so at most 16384 goals a request
constexpr int kMaxBatch = 64;           // data items or acks in one message
constexpr int kMaxDead = 32;            // agents the OC declares dead in one mission (docs/faults.md)
constexpr int kMaxHeard = 64;           // workers a collector reports news of in one state message
constexpr double kMaxDelay = 1e6;       // [s] a collector's delay a message may carry, either way

enum class Kind : uint8_t { kRequest = 1, kData = 2, kAck = 3, kState = 4 };
const char* kind_name(Kind k);

struct Header {
  Kind kind = Kind::kState;
  int16_t sender = 0;  // agent id, kOc
  int16_t dest = kBroadcast;
  uint32_t seq = 0;      // per sender: 0, 1, 2, ... (set by the runner)
  int64_t tick = -1;     // lockstep tick it was sent in (-1: wall clock)
  double t = 0.0;        // [s] mission time at sending
  Point2 pos;            // [m] sender's position at sending
  int32_t request = -1;  // newest request the sender knows, -1 none
  // How many of the OC's declarations of dead agents the sender knows, and
  // of the revocations among them (Role::known_declarations: 0 .. 2 kMaxDead).
  uint8_t dead = 0;
  // [s] a collector: how far behind its timetable it is at sending (< 0:
  // ahead), measured from what its robot reported; 0 from anyone else.
  double delay = 0.0;
};

// One part of goal request `request`: goals first_goal .. first_goal +
// total - 1 (ids are global: cycle-major), this part holding `count` of them
// from first_goal + part * kRequestPartGoals, as cells of the plan's grid
// (row-major index).
struct RequestPart {
  int32_t request = 0;
  double issued_at = 0.0;  // [s]
  int32_t first_goal = 0;
  int32_t total = 0;
  uint16_t part = 0, parts = 1;
  uint16_t count = 0;
  uint32_t cells[kRequestPartGoals];
  // The agents the OC has declared dead so far, in the order it declared
  // them (the plan every agent executes is mission::repair_plan of them).
  uint8_t dead_count = 0;
  int16_t dead[kMaxDead];
  // Bit i: the OC revoked dead[i]'s keys (docs/security.md, "Revocation"):
  // every message from it is dropped, and what it holds is lost with it.
  uint32_t dead_revoked = 0;
};
static_assert(kMaxDead <= 32, "RequestPart::dead_revoked has a bit per declaration");

// What happened to a goal (or to a whole request of one worker), carried to
// the OC under custody: kept by the sender until acked, resent at the next
// contact, de-duplicated by key at every receiver.
enum class ItemKind : uint8_t {
  kMeasured = 1,  // measured data of goal `key`
  kExpired = 2,   // goal `key` not measured before its deadline
  kDropped = 3,   // goal `key` measured, but its data could not be stored (buffer full)
  kSkipped = 4,   // a request never reached worker `by` before its deadline: its goals there expired (key: skipped_key)
  kUnreachable = 5,  // goal `key`: worker `by`'s robot could not reach it (its navigation gave up)
};
const char* item_kind_name(ItemKind k);

struct DataItem {
  int32_t key = 0;  // goal id (>= 0); kSkipped: skipped_key(request, worker) (< 0)
  ItemKind kind = ItemKind::kMeasured;
  int16_t by = -1;             // the worker that measured (expired, skipped) it
  double at = 0.0;             // [s] measured_at, or when it expired / was dropped / was given up
  int16_t picked_up_by = -1;   // the collector that took it from the worker, -1 none
  double picked_up_at = -1.0;  // [s]
  // [s] the deadline the worker applied to the goal (its request's, counted
  // from when the request reached it); +inf: none (a worker of the OC).
  double deadline = 0.0;
};
// Keys of skip notices: one per (request, worker), all negative.
constexpr int kMaxRequests = 100000;
inline int32_t skipped_key(int request, int worker) { return -(1 + request * kMaxTeam + worker); }
inline int skipped_request(int32_t key) { return static_cast<int>((-static_cast<int64_t>(key) - 1) / kMaxTeam); }
inline int skipped_worker(int32_t key) { return static_cast<int>((-static_cast<int64_t>(key) - 1) % kMaxTeam); }

struct DataBatch {
  uint16_t count = 0;
  DataItem items[kMaxBatch];
};

struct AckBatch {
  uint16_t count = 0;  // 0: "heard you" (the OC's reply to a state message)
  int32_t keys[kMaxBatch];
};

enum class RoleKind : uint8_t { kWorker = 1, kCollector = 2, kOcRole = 3 };
const char* role_kind_name(RoleKind r);

struct StateReport {
  RoleKind role = RoleKind::kWorker;
  uint16_t carried = 0;  // data items in custody (measured data)
  uint16_t notices = 0;  // expiry / drop / skip notices in custody
  uint16_t pending = 0;  // goals known and not yet measured
  int32_t measured = 0;  // goals measured so far
  // [s] a worker: when it next expects to be back in touch (its plan's end:
  // back in the coverage, or at its meeting); the OC waits that long, and
  // its timeout more, before it declares the worker dead. 0: now.
  double back_by = 0.0;
  // Collectors: when they last heard each of their workers (the OC's news
  // of workers it cannot hear; docs/faults.md, "Liveness").
  uint8_t heard_count = 0;
  int16_t heard_agent[kMaxHeard];
  double heard_at[kMaxHeard];  // [s] mission time
};

struct Message {
  Header h;
  union {
    RequestPart request;
    DataBatch data;
    AckBatch ack;
    StateReport state;
  };
  // Every byte of the body zeroed (whichever kind it becomes), then a
  // default header and state report.
  Message() {
    std::memset(static_cast<void*>(this), 0, sizeof(Message));
    new (&h) Header();
    new (&state) StateReport();
  }
};

}  // namespace agent
}  // namespace gather
