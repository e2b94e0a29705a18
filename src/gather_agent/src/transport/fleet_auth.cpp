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

#include "gather_core/error.hpp"
#include "gather_core/input_file.hpp"

namespace gather {
namespace agent {

static_assert(kKeyBytes == crypto_auth_hmacsha512256_KEYBYTES, "key size");
static_assert(kMacBytes == crypto_auth_hmacsha512256_BYTES, "MAC size");

namespace {

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

}  // namespace

FleetKey load_fleet_key(const std::string& path) {
  // Opened once, its mode checked on that descriptor (no check-then-open
  // gap), a symbolic link as the last component refused.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0)
    throw Error(path, errno == ELOOP ? std::string("the key file is a symbolic link: give the file itself")
                                     : std::string("cannot read the key file: ") + std::strerror(errno));
  struct stat st {};
  std::string text;
  const bool stat_ok = ::fstat(fd, &st) == 0;
  if (stat_ok && S_ISREG(st.st_mode) && (st.st_mode & 077) == 0 && st.st_size <= 4096) {
    char buf[4097];
    ssize_t n = 0, got;
    while (n < 4097 && (got = ::read(fd, buf + n, static_cast<std::size_t>(4097 - n))) > 0) n += got;
    text.assign(buf, static_cast<std::size_t>(std::max<ssize_t>(n, 0)));
    sodium_memzero(buf, sizeof buf);
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
  if (st.st_size > 4096 || text.size() > 4096)
    throw Error(path, "the key file is larger than 4096 bytes: not a gather fleet key");
  std::istringstream in(text);
  FleetKey k;
  bool have_id = false, have_key = false;
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) throw Error(path + ":" + std::to_string(no), "expected 'key_id: N' or 'key: HEX'");
    const std::string field = trim(line.substr(0, colon)), value = trim(line.substr(colon + 1));
    if ((field == "key_id" && have_id) || (field == "key" && have_key))
      throw Error(path + ":" + std::to_string(no), field + " given twice (a key file has one key_id and one key)");
    if (field == "key_id") {
      char* end = nullptr;
      errno = 0;
      const long v = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || errno != 0 || v < 1 || v > 32767)
        throw Error(path + ": key_id", "expected an integer in 1..32767");
      k.id = static_cast<int16_t>(v);
      have_id = true;
    } else if (field == "key") {
      std::size_t bin_len = 0;
      if (value.size() != 2 * kKeyBytes ||
          sodium_hex2bin(k.key.data(), k.key.size(), value.c_str(), value.size(), nullptr, &bin_len, nullptr) != 0 ||
          bin_len != kKeyBytes)
        throw Error(path + ": key", "expected " + std::to_string(2 * kKeyBytes) + " hexadecimal digits");
      have_key = true;
    } else {
      throw Error(path + ":" + std::to_string(no), "unknown field '" + quote_input(field, 40) + "' (key_id, key)");
    }
  }
  if (!have_id) throw Error(path + ": key_id", "missing");
  if (!have_key) throw Error(path + ": key", "missing");
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

std::optional<FleetKey> fleet_key_from_options(const std::string& key_file, bool insecure, const std::string& who,
                                               const std::string& key_flag, const std::string& insecure_flag) {
  if (!key_file.empty() && insecure) throw Error(key_flag, "give " + key_flag + " or " + insecure_flag + ", not both");
  if (key_file.empty() && !insecure)
    throw Error(key_flag, "fleet traffic is signed: give the fleet's key file (`gather keygen FILE` makes one), or " +
                              insecure_flag + " for an unsigned fleet (docs/security.md)");
  if (insecure) {
    std::fprintf(stderr,
                 "%s: WARNING: %s: fleet messages are neither signed nor checked; anyone on the network can forge, "
                 "change or replay them (docs/security.md)\n",
                 who.c_str(), insecure_flag.c_str());
    return std::nullopt;
  }
  return load_fleet_key(key_file);
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
    : key_(std::move(key)),
      channels_(std::move(channels)),
      senders_(senders),
      clock_(clock ? clock : &host_clock_),
      started_local_us_(clock_->local_us()),
      mac_only_(channels_.size(), false) {
  need_sodium();
  if (key_) crypto_auth_hmacsha512256_init(&keyed_, key_->key.data(), key_->key.size());
}

FleetAuth::~FleetAuth() { sodium_memzero(&keyed_, sizeof keyed_); }

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
  uint8_t fields[2 + 2 + 2 + 8 + 4];
  put_be(fields, static_cast<uint16_t>(head.version), 2);
  put_be(fields + 2, static_cast<uint16_t>(head.key_id), 2);
  put_be(fields + 4, static_cast<uint16_t>(head.sender), 2);
  put_be(fields + 6, static_cast<uint64_t>(head.counter), 8);
  put_be(fields + 14, static_cast<uint32_t>(size), 4);
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
