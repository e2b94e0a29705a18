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

namespace {

constexpr std::size_t kMaxTags = static_cast<std::size_t>(gather_lcm::fleet_envelope_t::MAX_TAGS);
static_assert(gather_lcm::fleet_envelope_t::TAG_BYTES == kTagBytes, "fleet_envelope_t's tags are kTagBytes");
constexpr std::size_t kTaggedFixed = 8 + 2 + 2 + 2 + 8 + 4 + 2 + 4;  // all but the payload, receivers and tags
int32_t be32(const uint8_t* b) {
  return static_cast<int32_t>(static_cast<uint32_t>(b[0]) << 24 | static_cast<uint32_t>(b[1]) << 16 |
                              static_cast<uint32_t>(b[2]) << 8 | static_cast<uint32_t>(b[3]));
}

}  // namespace

FleetEnvelopes::FleetEnvelopes(FleetAuth& auth, std::size_t max_payload)
    : auth_(auth), out_(max_payload + kTaggedFixed + kMaxTags * (2 + kTagBytes)) {
  e_.payload.reserve(max_payload);
  e_.receiver.reserve(kMaxTags);
  e_.tags.reserve(kMaxTags * kTagBytes);
}

int FleetEnvelopes::seal(const char* channel, int16_t sender, const uint8_t* payload, int n, const int16_t* receivers,
                         std::size_t count) {
  if (n < 0 || n > gather_lcm::fleet_envelope_t::MAX_PAYLOAD || count > kMaxTags) return -1;
  EnvelopeHead head;
  e_.payload.assign(payload, payload + n);
  e_.receiver.assign(receivers, receivers + count);
  e_.tags.resize(count * kTagBytes);
  if (!auth_.sign_tagged(channel, sender, e_.payload.data(), e_.payload.size(), receivers, count, head, e_.tags.data()))
    return -1;
  e_.version = head.version;
  e_.key_id = head.key_id;
  e_.sender = head.sender;
  e_.counter = head.counter;
  e_.size = n;
  e_.n_tags = static_cast<int16_t>(count);
  e_.tag_bytes = static_cast<int32_t>(count * kTagBytes);
  return e_.encode(out_.data(), 0, static_cast<int>(out_.size()));
}

FleetEnvelopes::Opened FleetEnvelopes::open(const char* channel, const void* data, int size, bool counters) {
  // Every size field is checked against the bytes received before the
  // decoder reads it (LCM's decode allocates what a size says). The
  // encoding: an 8-byte fingerprint, version, key_id, sender (2 bytes
  // each), counter (8), size (4, big endian), payload, n_tags (2),
  // receivers (2 each), tag_bytes (4), tags.
  constexpr int kSizeAt = 8 + 2 + 2 + 2 + 8;
  if (size < static_cast<int>(kTaggedFixed) || size > static_cast<int>(out_.size())) return Opened::kUndecodable;
  const uint8_t* b = static_cast<const uint8_t*>(data);
  const int64_t declared = be32(b + kSizeAt);
  if (declared < 0 || declared > size - static_cast<int>(kTaggedFixed)) return Opened::kUndecodable;
  if (declared > gather_lcm::fleet_envelope_t::MAX_PAYLOAD) return Opened::kOutOfRange;
  const uint8_t* after = b + kSizeAt + 4 + declared;
  const int64_t n_tags = static_cast<int16_t>(static_cast<uint16_t>(after[0] << 8 | after[1]));
  if (n_tags < 0 || static_cast<std::size_t>(n_tags) > kMaxTags) return Opened::kOutOfRange;
  if (kSizeAt + 4 + declared + 2 + 2 * n_tags + 4 + n_tags * static_cast<int64_t>(kTagBytes) != size)
    return Opened::kUndecodable;
  if (be32(after + 2 + 2 * n_tags) != n_tags * static_cast<int64_t>(kTagBytes)) return Opened::kUndecodable;
  // The generated decoder leaves an array as it was for a count of 0: empty
  // them first, so that nothing is checked against an earlier message.
  e_.payload.clear();
  e_.receiver.clear();
  e_.tags.clear();
  if (safe_decode(e_, data, size) != size || e_.payload.size() != static_cast<std::size_t>(e_.size) ||
      e_.receiver.size() != static_cast<std::size_t>(e_.n_tags) ||
      e_.tags.size() != static_cast<std::size_t>(e_.n_tags) * kTagBytes)
    return Opened::kUndecodable;
  const EnvelopeHead head{e_.version, e_.key_id, e_.sender, e_.counter};
  switch (auth_.verify_tagged(channel, head, e_.payload.data(), e_.payload.size(), e_.receiver.data(), e_.tags.data(),
                              e_.receiver.size(), counters)) {
    case Verdict::kAccepted: break;
    case Verdict::kNotForMe: return Opened::kNotForMe;
    default: return Opened::kRejected;
  }
  if (e_.version != gather_lcm::fleet_envelope_t::VERSION) return Opened::kWrongVersion;
  return Opened::kOk;
}

}  // namespace agent
}  // namespace gather
