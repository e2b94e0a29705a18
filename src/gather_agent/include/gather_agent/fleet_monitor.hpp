#pragma once
// What the OC knows about the fleet from the heartbeats it received.
#include <cstdint>
#include <string>
#include <vector>

#include "gather_agent/heartbeat.hpp"

namespace gather {

struct AgentRecord {
  bool heard = false;
  int64_t heartbeats = 0;      // messages accepted
  int64_t first_seq = -1;
  int64_t last_seq = -1;
  int64_t missed = 0;          // sequence numbers skipped (lost messages)
  int64_t out_of_order = 0;    // duplicates or older than the last accepted
  Role role = Role::kUnassigned;
  Point2 pose;                 // [m]
  double yaw = 0.0;            // [rad]
  double first_heard_s = 0.0;  // receiver clock [s]
  double last_heard_s = 0.0;   // receiver clock [s]
};

class FleetMonitor {
 public:
  enum class Verdict { kAccepted, kUndecodable, kWrongSchema, kUnknownAgent };

  explicit FleetMonitor(int agents) : agents_(static_cast<std::size_t>(agents)) {}

  // Decodes one raw LCM payload of the agent state channel and updates the
  // agent's record. Anything that does not decode, has another schema version
  // or names an agent outside 0..N-1 is counted and otherwise ignored.
  Verdict on_message(const void* data, int size, double now_s);

  const std::vector<AgentRecord>& agents() const { return agents_; }
  int heard() const;
  int64_t rejected() const { return rejected_; }

 private:
  std::vector<AgentRecord> agents_;
  int64_t rejected_ = 0;
};

}  // namespace gather
