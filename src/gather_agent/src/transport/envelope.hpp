#pragma once
// The signed envelope every LCM message of the project travels in
// (envelope_t, docs/security.md): sealing a payload with the fleet key and
// opening a received one, checking its size before anything is decoded,
// then its key id, MAC and counter (transport/fleet_auth). Shared by the
// fleet (LcmFleet) and the robot interface (LcmRobotLink). Internal to
// gather_agent_lib: it sees the generated envelope type.
#include <gather_lcm/envelope_t.hpp>
#include <gather_lcm/fleet_envelope_t.hpp>

#include <cstdint>
#include <vector>

#include "gather_agent/transport/fleet_auth.hpp"

namespace gather {
namespace agent {

class Envelopes {
 public:
  // Payloads of up to `max_payload` bytes; `auth` signs and checks.
  Envelopes(FleetAuth& auth, std::size_t max_payload);

  // The envelope of payload[0, n) from `sender` on `channel`: its bytes in
  // bytes() [0, returned), or -1 when it does not encode.
  int seal(const char* channel, int16_t sender, const uint8_t* payload, int n);
  const uint8_t* bytes() const { return out_.data(); }

  enum class Opened : uint8_t { kOk, kUndecodable, kOutOfRange, kWrongVersion, kRejected };
  // Opens a received envelope; on kOk, payload() [0, payload_size()) and
  // sender() are its content (valid until the next open). kRejected: the
  // signature, key or counter failed (FleetAuth counted why).
  // `counters` false: the key and MAC are checked, the counter is not
  // (FleetAuth::verify).
  Opened open(const char* channel, const void* data, int size, bool counters = true);
  const uint8_t* payload() const { return e_.payload.data(); }
  int payload_size() const { return e_.size; }
  int16_t sender() const { return e_.sender; }

 private:
  FleetAuth& auth_;
  gather_lcm::envelope_t e_;
  std::vector<uint8_t> out_;
};

// The fleet's envelope (fleet_envelope_t): a tag per receiver, each made
// with the key of its link to the sender (FleetAuth's per-link mode).
class FleetEnvelopes {
 public:
  FleetEnvelopes(FleetAuth& auth, std::size_t max_payload);

  // The envelope of payload[0, n) from `sender` on `channel` for
  // receivers[0, count): its bytes in bytes() [0, returned), or -1 when it
  // does not encode or this process holds no key for one of the receivers.
  int seal(const char* channel, int16_t sender, const uint8_t* payload, int n, const int16_t* receivers,
           std::size_t count);
  const uint8_t* bytes() const { return out_.data(); }

  // As Envelopes::open; kNotForMe: it carries no tag for this receiver.
  enum class Opened : uint8_t { kOk, kUndecodable, kOutOfRange, kWrongVersion, kRejected, kNotForMe };
  Opened open(const char* channel, const void* data, int size, bool counters = true);
  const uint8_t* payload() const { return e_.payload.data(); }
  int payload_size() const { return e_.size; }
  int16_t sender() const { return e_.sender; }
  // The receivers it was sent to (valid until the next open).
  const std::vector<int16_t>& receivers() const { return e_.receiver; }

 private:
  FleetAuth& auth_;
  gather_lcm::fleet_envelope_t e_;
  std::vector<uint8_t> out_;
};

// LCM's generated decode resizes a variable-length array to the count it
// reads before checking that the bytes are there: a negative count
// (int16) throws std::length_error. Any exception is an undecodable message.
template <typename T>
int safe_decode(T& msg, const void* data, int size) {
  try {
    return msg.decode(data, 0, size);
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace agent
}  // namespace gather
