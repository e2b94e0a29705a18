#include "envelope.hpp"

namespace gather {
namespace agent {

static_assert(kMacBytes == 32, "envelope_t.mac is 32 bytes");

Envelopes::Envelopes(FleetAuth& auth, std::size_t max_payload) : auth_(auth), out_(max_payload + 64) {
  e_.payload.reserve(max_payload);
}

int Envelopes::seal(const char* channel, int16_t sender, const uint8_t* payload, int n) {
  if (n < 0 || static_cast<std::size_t>(n) + 64 > out_.size()) return -1;
  EnvelopeHead head;
  e_.payload.assign(payload, payload + n);
  auth_.sign(channel, sender, e_.payload.data(), e_.payload.size(), head, e_.mac);
  e_.version = head.version;
  e_.key_id = head.key_id;
  e_.sender = head.sender;
  e_.counter = head.counter;
  e_.size = n;
  return e_.encode(out_.data(), 0, static_cast<int>(out_.size()));
}

Envelopes::Opened Envelopes::open(const char* channel, const void* data, int size, bool counters) {
  // The envelope's size field is checked before its payload is read (LCM's
  // decode allocates what the size says).
  // LCM's encoding: an 8-byte fingerprint, then version, key_id, sender
  // (2 bytes each), counter (8), size (4, big endian), payload, mac (32).
  constexpr int kSizeAt = 8 + 2 + 2 + 2 + 8, kFixed = kSizeAt + 4 + static_cast<int>(kMacBytes);
  if (size < kFixed || size > static_cast<int>(out_.size())) return Opened::kUndecodable;
  const uint8_t* b = static_cast<const uint8_t*>(data) + kSizeAt;
  const int64_t declared = static_cast<int32_t>(static_cast<uint32_t>(b[0]) << 24 | static_cast<uint32_t>(b[1]) << 16 |
                                                static_cast<uint32_t>(b[2]) << 8 | static_cast<uint32_t>(b[3]));
  if (declared != size - kFixed) return Opened::kUndecodable;
  if (declared > gather_lcm::envelope_t::MAX_PAYLOAD) return Opened::kOutOfRange;
  // The generated decoder leaves the payload as it was for a size of 0: empty
  // it first, so that a MAC is never checked against an earlier message.
  e_.payload.clear();
  if (safe_decode(e_, data, size) != size || e_.payload.size() != static_cast<std::size_t>(e_.size))
    return Opened::kUndecodable;
  const EnvelopeHead head{e_.version, e_.key_id, e_.sender, e_.counter};
  if (auth_.verify(channel, head, e_.payload.data(), e_.payload.size(), e_.mac, counters) != Verdict::kAccepted)
    return Opened::kRejected;
  if (e_.version != gather_lcm::envelope_t::VERSION) return Opened::kWrongVersion;
  return Opened::kOk;
}

}  // namespace agent
}  // namespace gather
