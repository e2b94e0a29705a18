#include "gather_agent/transport/fleet_auth.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "gather_agent/messages.hpp"
#include "gather_core/error.hpp"
#include "gather_core/input_file.hpp"

namespace gather {
namespace agent {

static_assert(kKeyBytes == crypto_auth_hmacsha512256_KEYBYTES, "key size");
static_assert(kMacBytes == crypto_auth_hmacsha512256_BYTES, "MAC size");
static_assert(kTagBytes >= crypto_generichash_blake2b_BYTES_MIN && kTagBytes <= crypto_generichash_blake2b_BYTES_MAX,
              "a tag is a BLAKE2b output");
static_assert(kKeyBytes >= crypto_generichash_blake2b_KEYBYTES_MIN &&
                  kKeyBytes <= crypto_generichash_blake2b_KEYBYTES_MAX,
              "a link key keys BLAKE2b");

namespace {

// A link's keyed state: BLAKE2b keyed with the link key, an output of
// kTagBytes (the output length is in BLAKE2b's parameter block: a tag is
// no truncation of a longer hash).
void keyed_state(const KeyRing::Key& key, crypto_generichash_blake2b_state& st) {
  crypto_generichash_blake2b_init(&st, key.data(), key.size(), kTagBytes);
}

void need_sodium() {
  if (sodium_init() < 0) throw RuntimeError("libsodium", "sodium_init failed");
}

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

void put_be(uint8_t* p, uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) p[i] = static_cast<uint8_t>(v & 0xff), v >>= 8;
}

// The envelope's signed fields, big endian: version, key id, sender (2
// bytes each), counter (8), payload size (4).
constexpr std::size_t kSignedFields = 2 + 2 + 2 + 8 + 4;
void signed_fields(const EnvelopeHead& head, std::size_t size, uint8_t* out) {
  put_be(out, static_cast<uint16_t>(head.version), 2);
  put_be(out + 2, static_cast<uint16_t>(head.key_id), 2);
  put_be(out + 4, static_cast<uint16_t>(head.sender), 2);
  put_be(out + 6, static_cast<uint64_t>(head.counter), 8);
  put_be(out + 14, static_cast<uint32_t>(size), 4);
}

}  // namespace

namespace {

constexpr long kMaxKeyFile = 512 * 1024;  // an agent's file: a line per link, a collector's up to its whole team

bool parse_hex_key(const std::string& value, KeyRing::Key& out) {
  std::size_t bin_len = 0;
  return value.size() == 2 * kKeyBytes &&
         sodium_hex2bin(out.data(), out.size(), value.c_str(), value.size(), nullptr, &bin_len, nullptr) == 0 &&
         bin_len == kKeyBytes;
}

bool parse_int(const std::string& value, long lo, long hi, long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtol(value.c_str(), &end, 10);
  return !value.empty() && *end == '\0' && errno == 0 && out >= lo && out <= hi;
}

}  // namespace

KeyRing load_key_ring(const std::string& path) {
  // Opened once, its mode checked on that descriptor (no check-then-open
  // gap), a symbolic link as the last component refused.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    throw Error(path, errno == ELOOP ? std::string("the key file is a symbolic link: give the file itself")
                                     : std::string("cannot read the key file: ") + std::strerror(errno));
  struct stat st {};
  std::string text;
  const bool stat_ok = ::fstat(fd, &st) == 0;
  if (stat_ok && S_ISREG(st.st_mode) && (st.st_mode & 077) == 0 && st.st_size <= kMaxKeyFile) {
    text.resize(static_cast<std::size_t>(kMaxKeyFile) + 1);
    std::size_t n = 0;
    ssize_t got;
    while (n < text.size() && (got = ::read(fd, &text[n], text.size() - n)) > 0) n += static_cast<std::size_t>(got);
    text.resize(n);
  }
  ::close(fd);
  if (!stat_ok) throw Error(path, "cannot read the key file");
  if (!S_ISREG(st.st_mode)) throw Error(path, "the key file is not a regular file");
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw Error(path,
                std::string("the key file is readable by group or others (mode ") + mode + "); chmod 600 " + path);
  }
  if (st.st_size > kMaxKeyFile || text.size() > static_cast<std::size_t>(kMaxKeyFile))
    throw Error(path, "the key file is larger than " + std::to_string(kMaxKeyFile) + " bytes: not a gather key file");
  std::istringstream in(text);
  sodium_memzero(&text[0], text.size());
  KeyRing k;
  bool have_id = false, have_key = false, have_agent = false, have_robot = false;
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    line = trim(line.substr(0, line.find('#')));  // a comment to the end of the line
    if (line.empty()) continue;
    const std::string at = path + ":" + std::to_string(no);
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) throw Error(at, "expected 'key_id: N' or 'key: HEX'");
    const std::string field = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    bool* seen = field == "key_id"      ? &have_id
                 : field == "key"       ? &have_key
                 : field == "agent"     ? &have_agent
                 : field == "robot_key" ? &have_robot
                                        : nullptr;
    if (seen && *seen) throw Error(at, field + " given twice (a key file has one " + field + ")");
    if (seen) *seen = true;
    long v = 0;
    if (field == "key_id") {
      if (!parse_int(value, 1, 32767, v)) throw Error(path + ": key_id", "expected an integer in 1..32767");
      k.id = static_cast<int16_t>(v);
    } else if (field == "key" || field == "robot_key") {
      if (!parse_hex_key(value, k.key))
        throw Error(path + ": " + field, "expected " + std::to_string(2 * kKeyBytes) + " hexadecimal digits");
    } else if (field == "agent") {
      if (!parse_int(value, 0, kMaxTeam - 1, v))
        throw Error(path + ": agent", "expected an agent id in 0.." + std::to_string(kMaxTeam - 1));
      k.agent = static_cast<int16_t>(v);
    } else if (field == "link") {
      const std::size_t space = value.find_first_of(" \t");
      KeyRing::Key key{};
      if (space == std::string::npos || !parse_int(value.substr(0, space), -1, kMaxTeam - 1, v) ||
          !parse_hex_key(trim(value.substr(space)), key))
        throw Error(at + ": link", "expected 'link: ID HEX' (ID -1 for the OC, or an agent id; " +
                                       std::to_string(2 * kKeyBytes) + " hexadecimal digits)");
      for (const auto& l : k.links)
        if (l.first == v) throw Error(at + ": link", "link " + std::to_string(v) + " given twice");
      k.links.emplace_back(static_cast<int16_t>(v), key);
      sodium_memzero(key.data(), key.size());
    } else {
      throw Error(at,
                  "unknown field '" + quote_input(field, 40) + "' (key_id, key; an agent's: agent, robot_key, link)");
    }
  }
  if (!have_id) throw Error(path + ": key_id", "missing");
  if (have_agent) {
    if (have_key) throw Error(path + ": key", "an agent's key file holds no master key (robot_key and links only)");
    if (!have_robot) throw Error(path + ": robot_key", "missing");
    if (k.links.empty()) throw Error(path + ": link", "missing (an agent has a link to the OC at least)");
    std::sort(k.links.begin(), k.links.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& l : k.links)
      if (l.first == k.agent)
        throw Error(path + ": link", "agent " + std::to_string(k.agent) + " has a link to itself");
  } else {
    if (have_robot || !k.links.empty())
      throw Error(path + ": agent", "missing (robot_key and link lines belong to an agent's key file)");
    if (!have_key) throw Error(path + ": key", "missing");
  }
  return k;
}

namespace {

FleetKey master_of(const KeyRing& ring, const std::string& path) {
  if (!ring.master())
    throw Error(path, "agent " + std::to_string(ring.agent) +
                          "'s key file: this needs the fleet's master key (the file `gather keygen FILE` made)");
  FleetKey k;
  k.id = ring.id;
  k.key = ring.key;
  return k;
}

}  // namespace

FleetKey load_fleet_key(const std::string& path) { return master_of(load_key_ring(path), path); }

KeyRing::KeyRing(const FleetKey& master_key) : id(master_key.id), agent(-1), key(master_key.key) {}

namespace {

// A link's number, the same either way round: (min + 1) << 16 | (max + 1).
// Its key's KDF subkey id, and where a receiver keeps its keyed state.
uint32_t link_index(int16_t a, int16_t b) {
  const int lo = std::min(a, b) + 1, hi = std::max(a, b) + 1;
  return static_cast<uint32_t>(lo) << 16 | static_cast<uint32_t>(hi);
}

}  // namespace

KeyRing::Key link_key(const FleetKey& master, int16_t a, int16_t b) {
  need_sodium();
  KeyRing::Key out{};
  crypto_kdf_derive_from_key(out.data(), out.size(), link_index(a, b), "gthrLINK", master.key.data());
  return out;
}

FleetKey robot_link_key(const KeyRing& ring) {
  FleetKey k;
  k.id = ring.id;
  if (!ring.master()) {
    k.key = ring.key;
    return k;
  }
  need_sodium();
  crypto_kdf_derive_from_key(k.key.data(), k.key.size(), 0, "gthrROBT", ring.key.data());
  return k;
}

KeyRing agent_key_ring(const FleetKey& master, int16_t agent, const std::vector<int16_t>& peers) {
  KeyRing k;
  k.id = master.id;
  k.agent = agent;
  k.key = robot_link_key(KeyRing(master)).key;
  for (int16_t p : peers) k.links.emplace_back(p, link_key(master, agent, p));
  std::sort(k.links.begin(), k.links.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return k;
}

FleetKey generate_fleet_key(int id) {
  need_sodium();
  FleetKey k;
  k.id = static_cast<int16_t>(id > 0 ? id : 1 + static_cast<int>(randombytes_uniform(32767)));
  crypto_auth_hmacsha512256_keygen(k.key.data());
  return k;
}

void write_fleet_key(const std::string& path, const FleetKey& key) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0)
    throw Error(path, errno == EEXIST ? "exists: not overwriting a key (remove it first)"
                                      : std::string("cannot create the key file: ") + std::strerror(errno));
  char hex[2 * kKeyBytes + 1];
  sodium_bin2hex(hex, sizeof hex, key.key.data(), key.key.size());
  std::ostringstream s;
  s << "# gather fleet key: the OC and every agent of one fleet use this file (docs/security.md).\n"
    << "# Keep it secret: mode 0600, copied only over a trusted channel.\n"
    << "key_id: " << key.id << "\nkey: " << hex << "\n";
  const std::string text = s.str();
  sodium_memzero(hex, sizeof hex);
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const bool closed = ::close(fd) == 0;
  if (!ok || !closed) throw Error(path, "cannot write the key file");
}

void write_key_ring(const std::string& path, const KeyRing& ring) {
  if (ring.master()) {
    FleetKey k;
    k.id = ring.id;
    k.key = ring.key;
    return write_fleet_key(path, k);
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0)
    throw Error(path, errno == EEXIST ? "exists: not overwriting a key (remove it first)"
                                      : std::string("cannot create the key file: ") + std::strerror(errno));
  char hex[2 * kKeyBytes + 1];
  std::ostringstream s;
  s << "# gather agent key: agent " << ring.agent << "'s keys for the links its plan gives it (docs/security.md).\n"
    << "# Only this robot gets it: mode 0600, copied only over a trusted channel.\n"
    << "key_id: " << ring.id << "\nagent: " << ring.agent << "\n";
  sodium_bin2hex(hex, sizeof hex, ring.key.data(), ring.key.size());
  s << "robot_key: " << hex << "\n";
  for (const auto& l : ring.links) {
    sodium_bin2hex(hex, sizeof hex, l.second.data(), l.second.size());
    s << "link: " << l.first << " " << hex << (l.first < 0 ? "  # the OC" : "") << "\n";
  }
  sodium_memzero(hex, sizeof hex);
  std::string text = s.str();
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  sodium_memzero(&text[0], text.size());
  const bool closed = ::close(fd) == 0;
  if (!ok || !closed) throw Error(path, "cannot write the key file");
}

std::optional<KeyRing> key_ring_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                             const std::string& key_flag, const std::string& insecure_flag) {
  if (!key_file.empty() && insecure) throw Error(key_flag, "give " + key_flag + " or " + insecure_flag + ", not both");
  if (key_file.empty() && !insecure)
    throw Error(key_flag,
                "fleet traffic is signed: give a key file (`gather keygen FILE` makes the master; "
                "`gather keygen --agent K` an agent's), or " +
                    insecure_flag + " for an unsigned fleet (docs/security.md)");
  if (insecure) {
    std::fprintf(stderr,
                 "%s: WARNING: %s: fleet messages are neither signed nor checked; anyone on the network can forge, "
                 "change or replay them (docs/security.md)\n",
                 who.c_str(), insecure_flag.c_str());
    return std::nullopt;
  }
  return load_key_ring(key_file);
}

std::optional<FleetKey> fleet_key_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                               const std::string& key_flag, const std::string& insecure_flag) {
  const std::optional<KeyRing> ring = key_ring_from_options(key_file, insecure, who, key_flag, insecure_flag);
  if (!ring) return std::nullopt;
  return master_of(*ring, key_file);
}

std::optional<FleetKey> robot_key_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                               const std::string& key_flag, const std::string& insecure_flag) {
  const std::optional<KeyRing> ring = key_ring_from_options(key_file, insecure, who, key_flag, insecure_flag);
  if (!ring) return std::nullopt;
  return robot_link_key(*ring);
}

FleetKey load_or_create_fleet_key(const std::string& path, bool* created) {
  struct stat st {};
  const bool exists = ::stat(path.c_str(), &st) == 0;
  if (!exists) write_fleet_key(path, generate_fleet_key());
  if (created) *created = !exists;
  return load_fleet_key(path);
}

std::string describe(const AuthCounters& a) {
  std::string s;
  auto add = [&](const char* what, int64_t n) {
    if (n > 0) s += (s.empty() ? "" : ", ") + std::string(what) + " " + std::to_string(n);
  };
  add("unsigned", a.unsigned_msgs);
  add("unknown key", a.unknown_key);
  add("bad MAC", a.bad_mac);
  add("replayed", a.replayed);
  add("wrong sender", a.wrong_sender);
  return s.empty() ? "none" : s;
}

FleetAuth::FleetAuth(std::optional<FleetKey> key, std::vector<std::string> channels, int senders,
                     const FleetClock* clock)
    : FleetAuth(std::move(key), std::nullopt, std::move(channels), senders, clock) {}

FleetAuth::FleetAuth(std::optional<KeyRing> ring, PerLinkTags, std::vector<std::string> channels, int senders,
                     const FleetClock* clock)
    : FleetAuth(std::nullopt, std::move(ring), std::move(channels), senders, clock) {}

FleetAuth::FleetAuth(std::optional<FleetKey> key, std::optional<KeyRing> ring, std::vector<std::string> channels,
                     int senders, const FleetClock* clock)
    : key_(std::move(key)),
      ring_(std::move(ring)),
      channels_(std::move(channels)),
      senders_(senders),
      clock_(clock ? clock : &host_clock_),
      started_local_us_(clock_->local_us()),
      mac_only_(channels_.size(), false) {
  need_sodium();
  if (key_) crypto_auth_hmacsha512256_init(&keyed_, key_->key.data(), key_->key.size());
  if (!ring_ || ring_->master()) return;
  for (const auto& l : ring_->links) {
    link_states_.emplace_back(link_index(ring_->agent, l.first), crypto_generichash_blake2b_state{});
    keyed_state(l.second, link_states_.back().second);
  }
  std::sort(link_states_.begin(), link_states_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
}

FleetAuth::~FleetAuth() {
  sodium_memzero(&keyed_, sizeof keyed_);
  for (auto& l : link_states_) sodium_memzero(&l.second, sizeof l.second);
  if (ring_) {
    sodium_memzero(ring_->key.data(), ring_->key.size());
    for (auto& l : ring_->links) sodium_memzero(l.second.data(), l.second.size());
  }
}

const crypto_generichash_blake2b_state* FleetAuth::link_state(int16_t a, int16_t b, bool signing) {
  if (!ring_ || a == b) return nullptr;
  if (!ring_->master() && a != ring_->agent && b != ring_->agent) return nullptr;  // not its link
  const uint32_t index = link_index(a, b);
  auto it = std::lower_bound(link_states_.begin(), link_states_.end(), index,
                             [](const auto& l, uint32_t i) { return l.first < i; });
  if (it != link_states_.end() && it->first == index) return &it->second;
  if (!ring_->master()) return nullptr;  // an agent holds its links' keys only
  // The master: the plan's links were derived by set_links(); before it,
  // to check a message, only the OC's links to agents (a bounded set), as
  // they are met; to sign one (its own choice), any pair.
  if (links_set_ || std::max(a, b) + 1 >= senders_ || std::min(a, b) < -1) return nullptr;
  if (!signing && a != -1 && b != -1) return nullptr;
  return derive(a, b);
}

const crypto_generichash_blake2b_state* FleetAuth::derive(int16_t a, int16_t b) {
  const uint32_t index = link_index(a, b);
  auto it = std::lower_bound(link_states_.begin(), link_states_.end(), index,
                             [](const auto& l, uint32_t i) { return l.first < i; });
  if (it != link_states_.end() && it->first == index) return &it->second;
  FleetKey master;
  master.id = ring_->id;
  master.key = ring_->key;
  KeyRing::Key key = link_key(master, a, b);
  sodium_memzero(master.key.data(), master.key.size());
  it = link_states_.emplace(it, index, crypto_generichash_blake2b_state{});
  keyed_state(key, it->second);
  sodium_memzero(key.data(), key.size());
  return &it->second;
}

void FleetAuth::digest_of(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
                          uint8_t* out) {
  uint8_t fields[kSignedFields];
  signed_fields(head, size, fields);
  crypto_generichash_blake2b_state st;
  crypto_generichash_blake2b_init(&st, nullptr, 0, 32);
  crypto_generichash_blake2b_update(&st, reinterpret_cast<const unsigned char*>(channel), std::strlen(channel) + 1);
  crypto_generichash_blake2b_update(&st, fields, sizeof fields);
  crypto_generichash_blake2b_update(&st, payload, size);
  crypto_generichash_blake2b_final(&st, out, 32);
}

namespace {

void tag_of(const crypto_generichash_blake2b_state& keyed, const uint8_t* digest, int16_t receiver, uint8_t* out) {
  uint8_t to[2];
  put_be(to, static_cast<uint16_t>(receiver), 2);
  crypto_generichash_blake2b_state st = keyed;
  crypto_generichash_blake2b_update(&st, digest, 32);
  crypto_generichash_blake2b_update(&st, to, sizeof to);
  crypto_generichash_blake2b_final(&st, out, kTagBytes);
}

}  // namespace

void FleetAuth::set_links(const FleetLinks& links) {
  if (!ring_ || !ring_->master()) return;
  // The plan's links, derived now; none other from here on (those met
  // before are dropped).
  for (auto& l : link_states_) sodium_memzero(&l.second, sizeof l.second);
  link_states_.clear();
  for (int a = 0; a < links.agents(); ++a) {
    derive(kOc, static_cast<int16_t>(a));
    const int16_t up = links.upstream()[static_cast<std::size_t>(a)];
    if (links.linked(static_cast<int16_t>(a), up)) derive(static_cast<int16_t>(a), up);
  }
  links_set_ = true;
}

bool FleetAuth::sign_tagged(const char* channel, int16_t sender, const uint8_t* payload, std::size_t size,
                            const int16_t* receivers, std::size_t n, EnvelopeHead& head, uint8_t* tags) {
  head.version = kTaggedVersion;
  head.sender = sender;
  const int c = channel_index(channel);
  int64_t fallback = 0;
  int64_t& last = (c >= 0 && sender >= -1 && sender + 1 < senders_) ? sent_slot(c, sender) : fallback;
  const int64_t counter = std::max(last + 1, clock_->now_us());
  head.counter = counter;
  if (!ring_) {
    head.key_id = 0;
    std::memset(tags, 0, n * kTagBytes);
    last = counter;
    return true;
  }
  head.key_id = ring_->id;
  uint8_t digest[32];
  digest_of(channel, head, payload, size, digest);
  for (std::size_t i = 0; i < n; ++i) {
    const crypto_generichash_blake2b_state* keyed = link_state(sender, receivers[i], /*signing=*/true);
    if (!keyed) return false;
    tag_of(*keyed, digest, receivers[i], tags + i * kTagBytes);
  }
  last = counter;
  return true;
}

Verdict FleetAuth::verify_tagged(const char* channel, const EnvelopeHead& head, const uint8_t* payload,
                                 std::size_t size, const int16_t* receivers, const uint8_t* tags, std::size_t n,
                                 bool counters) {
  if (!ring_) return Verdict::kAccepted;
  if (head.key_id == 0) return ++counters_.unsigned_msgs, Verdict::kUnsigned;
  if (head.key_id != ring_->id || head.version != kTaggedVersion) return ++counters_.unknown_key, Verdict::kUnknownKey;
  const int c = channel_index(channel);
  if (c < 0 || head.sender < -1 || head.sender + 1 >= senders_) return ++counters_.bad_mac, Verdict::kBadMac;
  uint8_t digest[32], expected[kTagBytes];
  // A tag `i` made with the key of its receiver's link to the sender.
  auto good = [&](std::size_t i) {
    const crypto_generichash_blake2b_state* keyed = link_state(head.sender, receivers[i]);
    if (!keyed) return false;  // no such link: nobody holds a key for it
    tag_of(*keyed, digest, receivers[i], expected);
    return crypto_verify_16(expected, tags + i * kTagBytes) == 0;
  };
  if (ring_->master()) {
    // The master checks every tag: a robot can make good tags for its own
    // links only, so a message it passes off as another's fails here.
    if (n == 0) return ++counters_.bad_mac, Verdict::kBadMac;
    digest_of(channel, head, payload, size, digest);
    for (std::size_t i = 0; i < n; ++i)
      if (!good(i)) return ++counters_.bad_mac, Verdict::kBadMac;
  } else {
    std::size_t which = n;
    for (std::size_t i = 0; i < n && which == n; ++i)
      if (receivers[i] == ring_->agent) which = i;
    if (which == n) return ++not_for_me_, Verdict::kNotForMe;
    digest_of(channel, head, payload, size, digest);
    if (!good(which)) return ++counters_.bad_mac, Verdict::kBadMac;
  }
  if (!counters || mac_only_[static_cast<std::size_t>(c)]) return Verdict::kAccepted;
  return check_counter(c, head);
}

void FleetAuth::reserve(int team) {
  const std::size_t n = static_cast<std::size_t>(std::clamp(team + 1, 0, senders_)) * channels_.size();
  if (accepted_.size() < n) accepted_.resize(n);
  if (!in_order_only_ && windows_.size() < n) windows_.resize(n);
}

void FleetAuth::start_now() { started_local_us_ = clock_->local_us(); }

void FleetAuth::mac_only(const char* channel) {
  const int c = channel_index(channel);
  if (c >= 0) mac_only_[static_cast<std::size_t>(c)] = true;
}

int FleetAuth::channel_index(const char* channel) const {
  for (std::size_t i = 0; i < channels_.size(); ++i)
    if (channels_[i] == channel) return static_cast<int>(i);
  return -1;
}

std::size_t FleetAuth::slot_index(int channel, int16_t sender) const {
  return static_cast<std::size_t>(sender + 1) * channels_.size() + static_cast<std::size_t>(channel);
}

int64_t& FleetAuth::sent_slot(int channel, int16_t sender) {
  const std::size_t i = slot_index(channel, sender);
  if (i >= sent_.size()) sent_.resize(i + 1, 0);
  return sent_[i];
}

FleetAuth::Seen& FleetAuth::seen_slot(int channel, int16_t sender) {
  const std::size_t i = slot_index(channel, sender);
  if (i >= accepted_.size()) accepted_.resize(i + 1);
  return accepted_[i];
}

FleetAuth::Window& FleetAuth::window_slot(int channel, int16_t sender) {
  const std::size_t i = slot_index(channel, sender);
  if (i >= windows_.size()) windows_.resize(i + 1);
  return windows_[i];
}

bool FleetAuth::Window::holds(int64_t c) const {
  for (std::size_t i = 0; i < held; ++i)
    if (below[i] == c) return true;
  return false;
}

void FleetAuth::Window::keep(int64_t c, int64_t& floor) {
  if (held < below.size()) {
    below[held++] = c;
    return;
  }
  std::size_t lowest = 0;
  for (std::size_t i = 1; i < below.size(); ++i)
    if (below[i] < below[lowest]) lowest = i;
  if (c < below[lowest]) {  // below all it keeps: it becomes the floor itself
    floor = std::max(floor, c);
    return;
  }
  floor = std::max(floor, below[lowest]);
  below[lowest] = c;
}

void FleetAuth::mac_of(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
                       uint8_t* out) const {
  // channel NUL | version | key id | sender | counter | payload size (big endian) | payload
  uint8_t fields[kSignedFields];
  signed_fields(head, size, fields);
  crypto_auth_hmacsha512256_state st = keyed_;
  crypto_auth_hmacsha512256_update(&st, reinterpret_cast<const unsigned char*>(channel), std::strlen(channel) + 1);
  crypto_auth_hmacsha512256_update(&st, fields, sizeof fields);
  crypto_auth_hmacsha512256_update(&st, payload, size);
  crypto_auth_hmacsha512256_final(&st, out);
}

void FleetAuth::sign(const char* channel, int16_t sender, const uint8_t* payload, std::size_t size, EnvelopeHead& head,
                     uint8_t* mac) {
  head.version = kVersion;
  head.sender = sender;
  const int c = channel_index(channel);
  int64_t fallback = 0;
  int64_t& last = (c >= 0 && sender >= -1 && sender + 1 < senders_) ? sent_slot(c, sender) : fallback;
  last = std::max(last + 1, clock_->now_us());
  head.counter = last;
  if (!key_) {
    head.key_id = 0;
    std::memset(mac, 0, kMacBytes);
    return;
  }
  head.key_id = key_->id;
  mac_of(channel, head, payload, size, mac);
}

Verdict FleetAuth::verify(const char* channel, const EnvelopeHead& head, const uint8_t* payload, std::size_t size,
                          const uint8_t* mac, bool counters) {
  if (!key_) return Verdict::kAccepted;
  if (head.key_id == 0) return ++counters_.unsigned_msgs, Verdict::kUnsigned;
  if (head.key_id != key_->id || head.version != kVersion) return ++counters_.unknown_key, Verdict::kUnknownKey;
  const int c = channel_index(channel);
  if (c < 0 || head.sender < -1 || head.sender + 1 >= senders_) return ++counters_.bad_mac, Verdict::kBadMac;
  uint8_t expected[kMacBytes];
  mac_of(channel, head, payload, size, expected);
  if (crypto_verify_32(expected, mac) != 0) return ++counters_.bad_mac, Verdict::kBadMac;
  if (!counters || mac_only_[static_cast<std::size_t>(c)]) return Verdict::kAccepted;
  return check_counter(c, head);
}

Verdict FleetAuth::check_counter(int c, const EnvelopeHead& head) {
  Seen& seen = seen_slot(c, head.sender);
  const int64_t counter = head.counter;
  if (seen.newest == 0) {
    // When this receiver started, in the fleet's time (its offset may have
    // been measured since).
    const int64_t started_us = started_local_us_ + clock_->offset_us();
    if (counter < started_us - kClockSkewUs || counter > clock_->now_us() + kClockSkewUs)
      return ++counters_.replayed, Verdict::kReplayed;  // sent before this receiver started: a capture
    seen.newest = counter;
    // Out of order after it, only what was sent since this receiver started
    // (as for the first one): captures of earlier traffic stay refused.
    seen.floor = started_us - kClockSkewUs - 1;
    return Verdict::kAccepted;
  }
  if (counter > seen.newest) {
    if (!in_order_only_) window_slot(c, head.sender).keep(seen.newest, seen.floor);
    seen.newest = counter;
    return Verdict::kAccepted;
  }
  // At or below the newest: once, within the reorder window.
  if (in_order_only_ || counter == seen.newest || counter <= seen.floor || counter < seen.newest - kReorderUs)
    return ++counters_.replayed, Verdict::kReplayed;
  Window& window = window_slot(c, head.sender);
  if (window.holds(counter)) return ++counters_.replayed, Verdict::kReplayed;
  window.keep(counter, seen.floor);
  ++reordered_;
  return Verdict::kAccepted;
}

}  // namespace agent
}  // namespace gather
