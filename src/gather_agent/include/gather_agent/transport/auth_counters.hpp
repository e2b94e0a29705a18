#pragma once
// Why a receiver dropped fleet messages before decoding them (signed fleet
// traffic, docs/security.md): counted per reason by the LCM transport,
// reported in the tick replies, agents.csv and mission.yaml.
#include <cstdint>

namespace gather {
namespace agent {

struct AuthCounters {
  int64_t unsigned_msgs = 0;  // no signature (key id 0) while a key is in use
  int64_t unknown_key = 0;    // signed with another key id (or envelope version)
  int64_t bad_mac = 0;        // the MAC does not match: forged, or changed on the way
  int64_t replayed = 0;       // counter not above the last accepted one from that sender and channel, or too old
  int64_t wrong_sender = 0;   // the message's own sender differs from the signed one
  int64_t total() const { return unsigned_msgs + unknown_key + bad_mac + replayed + wrong_sender; }
  AuthCounters& operator+=(const AuthCounters& o) {
    unsigned_msgs += o.unsigned_msgs, unknown_key += o.unknown_key, bad_mac += o.bad_mac;
    replayed += o.replayed, wrong_sender += o.wrong_sender;
    return *this;
  }
};

}  // namespace agent
}  // namespace gather
