#pragma once
// Authenticated fleet traffic (docs/security.md): every fleet message is
// signed with the fleet's shared key, and every receiver checks the
// signature, the key id and the sender's counter before it decodes anything.
//
// The MAC is libsodium's crypto_auth_hmacsha512256 (HMAC-SHA-512-256) over
// the channel name, the envelope's version, key id, sender and counter, and
// the payload (the message's own LCM encoding). The counter is per sender
// and channel and strictly increasing: max(last + 1, wall-clock time in us),
// so a restarted process continues above what it sent before its restart
// without keeping any state (as long as its clock does not step back). A
// receiver accepts each counter from a sender on a channel once: above the
// highest it accepted from them, or below it within a sliding window (at
// most kReorderUs older, and above all but the kReorderSlots highest it
// accepted below that one), so a message the radio delivered out of order
// passes and its replay does not (the anti-replay window of IPsec and DTLS,
// over time-based counters). The first counter it hears from a sender on a
// channel passes only when it was sent after this receiver started (within
// kClockSkewUs for clocks that differ), so a receiver that starts or
// restarts is not open to captures of earlier traffic either. No code here sees LCM types: LcmFleet
// wraps and unwraps the envelope.
#include <sodium/crypto_auth_hmacsha512256.h>
#include <sodium/crypto_generichash_blake2b.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gather_agent/transport/auth_counters.hpp"
#include "gather_agent/transport/fleet_clock.hpp"
#include "gather_agent/transport/fleet_links.hpp"

namespace gather {
namespace agent {

constexpr std::size_t kKeyBytes = 32;  // crypto_auth_hmacsha512256_KEYBYTES
constexpr std::size_t kMacBytes = 32;  // crypto_auth_hmacsha512256_BYTES
constexpr std::size_t kTagBytes = 16;  // a per-receiver tag: keyed BLAKE2b, 16 bytes

// The fleet's shared secret and its id (1..32767; 0 marks an unsigned
// message on the wire).
struct FleetKey {
  int16_t id = 0;
  std::array<uint8_t, kKeyBytes> key{};
};

// What a process holds to sign and check fleet traffic (docs/security.md):
// the OC's master key, from which every link's key is derived, or one
// agent's keys: those of its links (the OC, and its collector or its
// workers), each derived from the master with libsodium's KDF, and the key
// of its robot link. An agent's keys authenticate it to its links only: a
// robot taken in the field can sign as itself, to them, and nothing else.
struct KeyRing {
  using Key = std::array<uint8_t, kKeyBytes>;
  int16_t id = 0;                              // the master's key id (1..32767), on every message
  int16_t agent = -1;                          // whose keys: -1 (kOc) the master's
  Key key{};                                   // the master key; an agent's: its robot link's key
  std::vector<std::pair<int16_t, Key>> links;  // an agent's: link peer (-1: the OC) -> key, by peer
  bool master() const { return agent < 0; }
  KeyRing() = default;
  KeyRing(const FleetKey& master_key);  // NOLINT(google-explicit-constructor): a master is a key ring
};

// The key of the link between `a` and `b` (ids: -1 the OC, agents 0..),
// the same either way round: crypto_kdf_derive_from_key(master, subkey
// (min + 1) << 16 | (max + 1), context "gthrLINK").
KeyRing::Key link_key(const FleetKey& master, int16_t a, int16_t b);
// The robot link's key (an agent and its robot's driver): from a master,
// crypto_kdf_derive_from_key(master, 0, "gthrROBT"); an agent's, as its
// file gives it.
FleetKey robot_link_key(const KeyRing& ring);
// Agent `agent`'s keys for the links `peers` (FleetLinks::peers).
KeyRing agent_key_ring(const FleetKey& master, int16_t agent, const std::vector<int16_t>& peers);

// Reads a key file: the master (write_fleet_key) or an agent's
// (write_key_ring). Throws gather::Error naming the file (and the field) as
// load_fleet_key does.
KeyRing load_key_ring(const std::string& path);
// Writes an agent's keys to `path` (mode 0600, never over a file).
void write_key_ring(const std::string& path, const KeyRing& ring);
// The keys a process runs with (fleet_key_from_options, for either kind of file).
std::optional<KeyRing> key_ring_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                             const std::string& key_flag = "--key-file",
                                             const std::string& insecure_flag = "--insecure");

// Reads a master key file written by write_fleet_key (an agent's file is
// refused: the OC's side needs the master). Throws gather::Error naming
// the file (and the field) when it cannot be read, is readable by group or
// others (mode & 077: the exit status is 2, as for every bad input), or is
// malformed.
FleetKey load_fleet_key(const std::string& path);

// A new random key (libsodium's randombytes), its id random in 1..32767
// unless `id` > 0.
FleetKey generate_fleet_key(int id = 0);

// Writes `key` to `path`, created with mode 0600; refuses (gather::Error) to
// overwrite an existing file.
void write_fleet_key(const std::string& path, const FleetKey& key);

// The key a process runs with, from its command line: `key_file` loaded
// (load_fleet_key), or none with `insecure`, after a warning on stderr
// naming `who`. Throws gather::Error(flag, ...) when both or neither are
// given.
std::optional<FleetKey> fleet_key_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                               const std::string& key_flag = "--key-file",
                                               const std::string& insecure_flag = "--insecure");

// The robot link's key a process runs with (robot_link_key of either kind
// of key file; none with `insecure`), as key_ring_from_options.
std::optional<FleetKey> robot_key_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                               const std::string& key_flag = "--key-file",
                                               const std::string& insecure_flag = "--insecure");

// The key at `path`, made there first (generate_fleet_key, mode 0600) when
// no file exists; `created` tells which.
FleetKey load_or_create_fleet_key(const std::string& path, bool* created = nullptr);

// One line: the counters by reason ("bad MAC 3, replayed 12"), or "none".
std::string describe(const AuthCounters& a);

// The envelope's fields that are signed (the payload aside).
struct EnvelopeHead {
  int16_t version = 0;
  int16_t key_id = 0;
  int16_t sender = 0;
  int64_t counter = 0;
};

// kNotForMe: a per-link message that carries no tag for this receiver (not
// a refusal: it was sent to others).
enum class Verdict : uint8_t { kAccepted, kUnsigned, kUnknownKey, kBadMac, kReplayed, kNotForMe };

// FleetAuth's per-link mode (below).
struct PerLinkTags {};

class FleetAuth {
 public:
  static constexpr int16_t kVersion = 1;        // a single MAC (the robot link: envelope_t)
  static constexpr int16_t kTaggedVersion = 3;  // per-link tags (the fleet: fleet_envelope_t)
  // How far the fleet's clocks may differ [us]: a sender's first message must
  // be stamped after the receiver started minus this, and at most this far
  // ahead of the receiver's clock.
  static constexpr int64_t kClockSkewUs = 2'000'000;
  // The reorder window: a message that arrives after newer ones from its
  // sender on its channel passes (once) when its counter is at most this
  // much older [us] than the newest accepted, and above all but the
  // kReorderSlots highest accepted below that newest one.
  static constexpr int64_t kReorderUs = 1'000'000;
  static constexpr std::size_t kReorderSlots = 16;

  // `key` empty: insecure mode (messages go unsigned, and nothing is checked).
  // `channels`: the channel names, in a fixed order (counters are kept per
  // sender and channel); `senders`: ids -1 (the OC) .. senders - 2.
  // `clock` (must outlive this; nullptr: the host's wall clock): the time
  // counters are signed with and checked against (an agent's: the fleet's
  // time, its host's clock corrected by the offset it measured to the OC).
  FleetAuth(std::optional<FleetKey> key, std::vector<std::string> channels, int senders,
            const FleetClock* clock = nullptr);
  // Per-link mode (the fleet): every message carries a tag for each of its
  // receivers, made with the key of the link between its sender and that
  // receiver (docs/security.md): tag = BLAKE2b with an output of kTagBytes,
  // keyed with the link key (libsodium's crypto_generichash), of
  // BLAKE2b-256(channel NUL, version, key id, sender, counter, payload
  // size, payload) | receiver. `ring` empty: insecure. A receiver with an
  // agent's keys checks its own tag; with the master (the OC, the robot
  // world, a replay) every tag.
  FleetAuth(std::optional<KeyRing> ring, PerLinkTags, std::vector<std::string> channels, int senders,
            const FleetClock* clock = nullptr);
  ~FleetAuth();
  FleetAuth(const FleetAuth&) = delete;
  FleetAuth& operator=(const FleetAuth&) = delete;

  bool secure() const { return key_.has_value() || ring_.has_value(); }

  // Fills `head` (version, key id, sender, the next counter) and `mac` for a
  // message from `sender` on `channel`. Unsigned mode: key id 0, zero MAC.
  void sign(const char* channel, int16_t sender, const uint8_t* payload, std::size_t size, EnvelopeHead& head,
            uint8_t* mac);

  // Per-link mode: fills `head` and, for each of receivers[0, n), its tag
  // (tags + i * kTagBytes). False (nothing signed) when this process holds
  // no key for one of them. Unsigned mode: key id 0, no tags needed.
  bool sign_tagged(const char* channel, int16_t sender, const uint8_t* payload, std::size_t size,
                   const int16_t* receivers, std::size_t n, EnvelopeHead& head, uint8_t* tags);
  // Per-link mode: checks a received envelope's tag for this receiver (with
  // the master: every tag, each receiver's), then its counter as verify()
  // does. kNotForMe (counted in not_for_me(), not a refusal): no tag for
  // this receiver. That the receivers are the message's own is LcmFleet's
  // check (it decodes the addresses).
  Verdict verify_tagged(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
                        const int16_t* receivers, const uint8_t* tags, std::size_t n, bool counters = true);
  // Per-link mode with the master: the links it checks and signs for (the
  // plan's: FleetLinks), their keys derived now. Until then only the OC's
  // links to agents 0..senders - 2 are derived, as they are met; never a
  // link the plan does not have (an outsider cannot make a receiver derive
  // and keep keys for pairs it names).
  void set_links(const FleetLinks& links);
  // A message whose tags passed but whose receivers are not those its kind
  // and addresses say (LcmFleet): counted as bad MAC.
  void count_bad_mac() { ++counters_.bad_mac; }

  // Per-link mode with an agent's keys: it checks (and takes) only what is
  // sent to it. The master, and insecure mode, take everything.
  bool sees_all() const { return !ring_ || ring_->master(); }
  // The agent whose keys these are (-1: the master's, or insecure).
  int16_t holder() const { return ring_ ? ring_->agent : int16_t{-1}; }
  int64_t not_for_me() const { return not_for_me_; }

  // Checks a received envelope; on kAccepted the sender's counter moves on.
  // Counts every refusal in counters(). Insecure mode accepts everything.
  // `counters` false: the key and the MAC only, nothing moves (an agent
  // before it knows the fleet's time counts traffic under another key).
  Verdict verify(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
                 const uint8_t* mac, bool counters = true);

  // Messages on `channel` are checked for their key and MAC only, not for
  // their counter: the clock exchange's channels, which carry what puts a
  // clock that is off right (a counter stamped by that clock proves
  // nothing). Their replays are harmless by design: an ask only earns an
  // answer that echoes its t0, and an answer counts only when it echoes the
  // asker's last t0, once (LcmFleet).
  void mac_only(const char* channel);

  // No reorder window on any channel: a counter must be above the newest
  // accepted (the robot link, whose messages supersede each other: a late
  // command must not undo a newer one, nor a late pose move the robot back).
  void in_order_only() { in_order_only_ = true; }

  // This receiver starts now (on its clock, which was just replaced): the
  // freshness window's lower end.
  void start_now();

  // A message that passed verify() but whose own sender field differs.
  void count_wrong_sender() { ++counters_.wrong_sender; }

  const AuthCounters& counters() const { return counters_; }
  // Messages accepted below their sender's newest counter on their channel
  // (delivered out of order, within the reorder window).
  int64_t reordered() const { return reordered_; }

  // Room for senders -1 .. team - 1 up front (no allocation while running).
  void reserve(int team);

 private:
  // One MAC under `key`, or per-link tags under `ring` (one of them, or
  // neither: insecure).
  FleetAuth(std::optional<FleetKey> key, std::optional<KeyRing> ring, std::vector<std::string> channels, int senders,
            const FleetClock* clock);
  int channel_index(const char* channel) const;
  void mac_of(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
              uint8_t* out) const;
  // The signed fields' digest (per-link mode), and the tag for `receiver` over it.
  static void digest_of(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
                        uint8_t* out);
  // The link's keyed BLAKE2b state (nullptr: no key for it), to sign with or
  // to check a received tag with (set_links() says which the master derives).
  const crypto_generichash_blake2b_state* link_state(int16_t a, int16_t b, bool signing = false);
  // The master: the link's keyed state, derived and kept.
  const crypto_generichash_blake2b_state* derive(int16_t a, int16_t b);
  // A sender's counter, once its signature passed (verify, verify_tagged).
  Verdict check_counter(int c, const EnvelopeHead& head);
  // What a receiver has accepted from one sender on one channel.
  struct Seen {
    int64_t newest = 0;  // the highest counter accepted; 0: none yet
    int64_t floor = 0;   // every counter at or below it is refused (it left the window)
  };
  // Its reorder window (none with in_order_only()).
  struct Window {
    std::array<int64_t, kReorderSlots> below{};  // accepted counters below `newest`, above `floor`
    uint8_t held = 0;                            // how many of `below` are in use
    // `c` (accepted, below the newest, above `floor`) joins the window; when
    // it is full the lowest leaves it and becomes the floor.
    void keep(int64_t c, int64_t& floor);
    bool holds(int64_t c) const;
  };
  std::size_t slot_index(int channel, int16_t sender) const;
  int64_t& sent_slot(int channel, int16_t sender);
  Seen& seen_slot(int channel, int16_t sender);
  Window& window_slot(int channel, int16_t sender);
  AuthCounters counters_;
  int64_t reordered_ = 0;

  std::optional<FleetKey> key_;
  std::optional<KeyRing> ring_;  // per-link mode
  // Per-link mode: each link's keyed state, by (min + 1) << 16 | (max + 1):
  // an agent's made up front, the master's as links are met.
  std::vector<std::pair<uint32_t, crypto_generichash_blake2b_state>> link_states_;
  int64_t not_for_me_ = 0;
  bool links_set_ = false;  // the master: set_links() was given the plan's links
  std::vector<std::string> channels_;
  int senders_;
  FleetClock host_clock_;       // when no clock is given: the host's (a reference)
  const FleetClock* clock_;     // the one counters are signed and checked on
  int64_t started_local_us_;    // this host's clock when this receiver started
  std::vector<bool> mac_only_;  // per channel
  bool in_order_only_ = false;
  // HMAC's state once the key is absorbed (its inner and outer pads hashed):
  // each message starts from a copy instead of hashing the key twice again.
  crypto_auth_hmacsha512256_state keyed_{};
  // [sender + 1][channel], grown to the highest sender met (a receiver meets
  // its team's; a signer its own id): 0 = none yet.
  std::vector<int64_t> sent_;    // last counter signed
  std::vector<Seen> accepted_;   // what was accepted
  std::vector<Window> windows_;  // their windows (not with in_order_only())
};

}  // namespace agent
}  // namespace gather
