#pragma once
// The simulated radio range: a receiver hears a message only when the radio
// model links the sender's position (carried in the message) and its own at
// that moment (RadioModel::linked: distance and walls), and, with an injected
// loss probability, only when the message is not lost. Loss is decided by a
// hash of (seed, sender, seq, receiver), so it does not depend on the order
// messages arrive in: the same run on any machine under any load.
//
// Every runner applies it to every message it hands a role, in one process
// and over LCM alike. Counted per receiver: received, dropped by the gate,
// dropped by loss.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_agent/messages.hpp"
#include "gather_agent/roles/role.hpp"

namespace gather {
namespace agent {

struct LinkCounters {
  int64_t sent = 0;      // messages this agent sent
  int64_t received = 0;  // messages for it that passed the gate
  int64_t gated = 0;     // messages for it out of radio range
  int64_t lost = 0;      // messages for it dropped by injected loss
  int64_t bad = 0;       // transport: undecodable, unknown version, oversized, from an unknown sender
  int64_t overflow = 0;  // inbox full: messages dropped (counted, never silent)
};

class RangeGate {
 public:
  // loss in [0, 1): probability a message in range is lost anyway.
  RangeGate(const TeamSetup& team, double loss = 0.0, uint64_t loss_seed = 1);
  enum class Verdict { kPass, kOutOfRange, kLost };
  Verdict admit(const Header& h, int16_t receiver, Point2 receiver_at) const;
  double loss() const { return loss_; }
  const TeamSetup& team() const { return team_; }

 private:
  const TeamSetup& team_;
  double loss_;
  uint64_t seed_;
};

// The inbox of `receiver` at `at` from the messages of one tick (`sent`):
// those addressed to it or broadcast, not its own, past the gate, in
// (sender, seq) order, at most `inbox.capacity()` (the rest counted as
// overflow). Updates `counters`.
void gather_inbox(const std::vector<Message>& sent, int16_t receiver, Point2 at, const RangeGate& gate,
                  LinkCounters& counters, std::vector<const Message*>& inbox);

}  // namespace agent
}  // namespace gather
