// The agent's on-disk journal (Journal: append-only records with a checksum,
// replay, compaction; JournalKeeper: what a role writes into it each step).
// Over 400 lines because the record format, its replay and its compaction
// must agree byte for byte, and reading them side by side is the check.
#include "gather_agent/runner/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

constexpr char kMagic[4] = {'G', 'J', 'R', 'N'};
constexpr uint32_t kVersion = 3;  // 2: an item's deadline, unreachable items; 3: revoked declarations
constexpr std::size_t kHeader = 4 + 4 + 4 + 8;
constexpr std::size_t kRecordHead = 4 + 4 + 1;
constexpr uint32_t kMaxPayload = 1u << 20;  // a progress snapshot of 16384 goals fits
enum Type : uint8_t { kPut = 1, kAck = 2, kProgress = 3, kPose = 4, kBatch = 5 };

// CRC-32 (IEEE 802.3, reflected), table built once.
uint32_t crc32(const uint8_t* p, std::size_t n, uint32_t crc = 0) {
  static uint32_t table[256];
  static bool built = false;
  if (!built) {
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      table[i] = c;
    }
    built = true;
  }
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

template <typename T>
void put_raw(std::vector<uint8_t>& out, const T& v) {
  const auto* b = reinterpret_cast<const uint8_t*>(&v);
  out.insert(out.end(), b, b + sizeof v);
}

// Reads a T at `at` when it fits before `end`.
template <typename T>
bool get_raw(const uint8_t*& at, const uint8_t* end, T& v) {
  if (static_cast<std::size_t>(end - at) < sizeof v) return false;
  std::memcpy(&v, at, sizeof v);
  at += sizeof v;
  return true;
}

void encode_item(std::vector<uint8_t>& out, const DataItem& it) {
  put_raw(out, it.key);
  put_raw(out, static_cast<uint8_t>(it.kind));
  put_raw(out, it.by);
  put_raw(out, it.at);
  put_raw(out, it.picked_up_by);
  put_raw(out, it.picked_up_at);
  put_raw(out, it.deadline);
}

bool decode_item(const uint8_t*& at, const uint8_t* end, DataItem& it) {
  uint8_t kind = 0;
  if (!get_raw(at, end, it.key) || !get_raw(at, end, kind) || !get_raw(at, end, it.by) || !get_raw(at, end, it.at) ||
      !get_raw(at, end, it.picked_up_by) || !get_raw(at, end, it.picked_up_at) || !get_raw(at, end, it.deadline))
    return false;
  if (kind < 1 || kind > 5) return false;
  it.kind = static_cast<ItemKind>(kind);
  return true;
}

void encode_progress(std::vector<uint8_t>& out, const Progress& p) {
  put_raw(out, p.resolved);
  put_raw(out, p.measured), put_raw(out, p.dropped), put_raw(out, p.expired), put_raw(out, p.skipped);
  put_raw(out, static_cast<uint32_t>(p.dead.size()));
  for (int16_t d : p.dead) put_raw(out, d);
  put_raw(out, p.revoked);
  put_raw(out, static_cast<uint32_t>(p.learned.size()));
  for (const mission::KnownGoal& g : p.learned) {
    put_raw(out, static_cast<int32_t>(g.id.value())), put_raw(out, static_cast<int32_t>(g.cell.row)),
        put_raw(out, static_cast<int32_t>(g.cell.col));
    put_raw(out, g.deadline);
  }
  put_raw(out, static_cast<uint32_t>(p.known.size()));
  for (GoalId k : p.known) put_raw(out, static_cast<int32_t>(k.value()));
}

bool decode_progress(const uint8_t* at, const uint8_t* end, Progress& p) {
  uint32_t n = 0;
  if (!get_raw(at, end, p.resolved) || !get_raw(at, end, p.measured) || !get_raw(at, end, p.dropped) ||
      !get_raw(at, end, p.expired) || !get_raw(at, end, p.skipped) || !get_raw(at, end, n) || n > kMaxDead)
    return false;
  p.dead.resize(n);
  for (int16_t& d : p.dead)
    if (!get_raw(at, end, d)) return false;
  if (!get_raw(at, end, p.revoked) || (n < 32 && (p.revoked >> n) != 0)) return false;
  if (!get_raw(at, end, n) || n > kMaxRequestParts * kRequestPartGoals) return false;
  p.learned.resize(n);
  for (mission::KnownGoal& g : p.learned) {
    int32_t id = 0, row = 0, col = 0;
    if (!get_raw(at, end, id) || !get_raw(at, end, row) || !get_raw(at, end, col) || !get_raw(at, end, g.deadline))
      return false;
    g.id = GoalId(id), g.cell = Cell{row, col};
  }
  if (!get_raw(at, end, n) || n > kMaxRequestParts * kRequestPartGoals) return false;
  p.known.resize(n);
  for (GoalId& k : p.known) {
    int32_t id = 0;
    if (!get_raw(at, end, id)) return false;
    k = GoalId(id);
  }
  return at == end;
}

}  // namespace

std::string journal_path(const std::string& dir, int agent) {
  return dir + "/agent_" + std::to_string(agent) + ".journal";
}

Journal::Journal(std::string path, int agent, uint64_t run) : path_(std::move(path)), agent_(agent), run_(run) {
  std::error_code ec;
  const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd_ < 0) throw Error(path_, std::string("cannot open the journal: ") + std::strerror(errno));
  pending_.reserve(64 * 1024);
  scratch_.reserve(64 * 1024);
  batch_.reserve(64 * 1024);
}

Journal::~Journal() {
  if (fd_ >= 0) ::close(fd_);
}

void Journal::header(std::vector<uint8_t>& out) const {
  out.insert(out.end(), kMagic, kMagic + 4);
  put_raw(out, kVersion);
  put_raw(out, static_cast<int32_t>(agent_));
  put_raw(out, run_);
}

void Journal::write_all(int fd, const uint8_t* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw RuntimeError(path_, std::string("cannot write the journal: ") + std::strerror(errno));
    data += w, n -= static_cast<std::size_t>(w);
  }
}

void Journal::reset() {
  pending_.clear();
  if (::ftruncate(fd_, 0) != 0 || ::lseek(fd_, 0, SEEK_SET) < 0)
    throw RuntimeError(path_, std::string("cannot truncate the journal: ") + std::strerror(errno));
  scratch_.clear();
  header(scratch_);
  write_all(fd_, scratch_.data(), scratch_.size());
  if (::fdatasync(fd_) != 0) throw RuntimeError(path_, std::string("cannot sync the journal: ") + std::strerror(errno));
  bytes_ = scratch_.size();
  compacted_ = 0;
}

// Applies the record at `at` (a batch: each record in it) to `s`; the end
// of the record, or nullptr when it is torn, corrupt or unknown.
static const uint8_t* read_records(const uint8_t* at, const uint8_t* end, JournalState& s, bool top) {
  uint32_t n = 0, crc = 0;
  const uint8_t* p = at;
  if (!get_raw(p, end, n) || !get_raw(p, end, crc) || n > kMaxPayload || static_cast<std::size_t>(end - p) < 1 + n)
    return nullptr;
  if (crc32(p, 1 + n) != crc) return nullptr;
  const uint8_t type = p[0];
  const uint8_t* body = p + 1;
  const uint8_t* body_end = body + n;
  switch (type) {
    case kBatch: {
      if (!top) return nullptr;
      JournalState t = s;  // all of the batch, or none of it
      for (const uint8_t* q = body; q < body_end;) {
        q = read_records(q, body_end, t, false);
        if (!q) return nullptr;
      }
      s = std::move(t);
      return body_end;
    }
    case kPut: {
      DataItem it;
      if (!decode_item(body, body_end, it)) return nullptr;
      bool held = false;
      for (const DataItem& x : s.custody) held = held || x.key == it.key;
      if (!held) s.custody.push_back(it);
      break;
    }
    case kAck: {
      int32_t key = 0;
      if (!get_raw(body, body_end, key)) return nullptr;
      for (std::size_t i = 0; i < s.custody.size(); ++i)
        if (s.custody[i].key == key) {
          s.custody.erase(s.custody.begin() + static_cast<long>(i));
          break;
        }
      break;
    }
    case kProgress: {
      Progress p2;
      if (!decode_progress(body, body_end, p2)) return nullptr;
      s.progress = std::move(p2);
      s.have_progress = true;
      break;
    }
    case kPose:
      if (!get_raw(body, body_end, s.pose.x) || !get_raw(body, body_end, s.pose.y) ||
          !get_raw(body, body_end, s.pose_t))
        return nullptr;
      s.have_pose = true;
      break;
    default: return nullptr;
  }
  ++s.records;
  return body_end;
}

JournalState Journal::replay() {
  JournalState s;
  struct stat st {};
  if (::fstat(fd_, &st) != 0)
    throw RuntimeError(path_, std::string("cannot read the journal: ") + std::strerror(errno));
  std::vector<uint8_t> data(static_cast<std::size_t>(st.st_size));
  if (::pread(fd_, data.data(), data.size(), 0) != static_cast<ssize_t>(data.size()))
    throw RuntimeError(path_, std::string("cannot read the journal: ") + std::strerror(errno));
  std::vector<uint8_t> expect;
  header(expect);
  if (data.size() < kHeader || std::memcmp(data.data(), expect.data(), kHeader) != 0) {
    reset();  // new, or another run's: nothing to replay
    return s;
  }
  s.matched = true;
  const uint8_t* at = data.data() + kHeader;
  const uint8_t* end = data.data() + data.size();
  const uint8_t* good = at;
  // A step's records come in one batch record (one CRC): a crash during its
  // write loses the whole step, never half of it.
  while (at < end) {
    const uint8_t* next = read_records(at, end, s, true);
    if (!next) break;
    at = good = next;
  }
  bytes_ = static_cast<std::size_t>(good - data.data());
  if (good != end) {
    s.cut = true;
    if (::ftruncate(fd_, static_cast<off_t>(bytes_)) != 0)
      throw RuntimeError(path_, std::string("cannot cut the journal's torn tail: ") + std::strerror(errno));
  }
  if (::lseek(fd_, static_cast<off_t>(bytes_), SEEK_SET) < 0)
    throw RuntimeError(path_, std::string("cannot seek the journal: ") + std::strerror(errno));
  return s;
}

void Journal::record(uint8_t type, const void* payload, std::size_t n) {
  const std::size_t at = pending_.size();
  put_raw(pending_, static_cast<uint32_t>(n));
  put_raw(pending_, uint32_t{0});
  pending_.push_back(type);
  const auto* b = static_cast<const uint8_t*>(payload);
  pending_.insert(pending_.end(), b, b + n);
  const uint32_t crc = crc32(pending_.data() + at + 8, 1 + n);
  std::memcpy(pending_.data() + at + 4, &crc, 4);
}

void Journal::put(const DataItem& item) {
  durable_ = true;
  scratch_.clear();
  encode_item(scratch_, item);
  record(kPut, scratch_.data(), scratch_.size());
}

void Journal::acked(const DataItem& item) {
  durable_ = true;
  record(kAck, &item.key, sizeof item.key);
}

void Journal::progress(const Progress& p) {
  durable_ = true;
  scratch_.clear();
  encode_progress(scratch_, p);
  record(kProgress, scratch_.data(), scratch_.size());
}

void Journal::pose(Point2 at, double t) {
  double v[3] = {at.x, at.y, t};
  record(kPose, v, sizeof v);
}

bool Journal::sync() {
  if (pending_.empty()) return false;
  // One batch record: the step's records all come back, or none.
  batch_.clear();
  put_raw(batch_, static_cast<uint32_t>(pending_.size()));
  put_raw(batch_, uint32_t{0});
  batch_.push_back(kBatch);
  batch_.insert(batch_.end(), pending_.begin(), pending_.end());
  const uint32_t crc = crc32(batch_.data() + 8, 1 + pending_.size());
  std::memcpy(batch_.data() + 4, &crc, 4);
  try {
    write_all(fd_, batch_.data(), batch_.size());
  } catch (...) {  // a short write: cut back to the last whole batch
    if (::ftruncate(fd_, static_cast<off_t>(bytes_)) == 0) ::lseek(fd_, static_cast<off_t>(bytes_), SEEK_SET);
    pending_.clear();
    throw;
  }
  if (durable_ && ::fdatasync(fd_) != 0)
    throw RuntimeError(path_, std::string("cannot sync the journal: ") + std::strerror(errno));
  bytes_ += batch_.size();
  pending_.clear();
  const bool synced = durable_;
  durable_ = false;
  return synced;
}

void Journal::compact(const JournalState& state) {
  const std::string tmp = path_ + ".tmp";
  pending_.clear();
  for (const DataItem& it : state.custody) put(it);
  if (state.have_progress) progress(state.progress);
  if (state.have_pose) pose(state.pose, state.pose_t);
  std::vector<uint8_t> all;
  header(all);
  put_raw(all, static_cast<uint32_t>(pending_.size()));
  put_raw(all, uint32_t{0});
  all.push_back(kBatch);
  all.insert(all.end(), pending_.begin(), pending_.end());
  const uint32_t crc = crc32(all.data() + kHeader + 8, 1 + pending_.size());
  std::memcpy(all.data() + kHeader + 4, &crc, 4);
  pending_.clear();
  durable_ = false;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) throw RuntimeError(tmp, std::string("cannot write the journal: ") + std::strerror(errno));
  try {
    write_all(fd, all.data(), all.size());
  } catch (...) {
    ::close(fd);
    throw;
  }
  const bool synced = ::fsync(fd) == 0;
  if (::close(fd) != 0 || !synced)
    throw RuntimeError(tmp, std::string("cannot sync the journal: ") + std::strerror(errno));
  if (std::rename(tmp.c_str(), path_.c_str()) != 0)
    throw RuntimeError(path_, std::string("cannot replace the journal: ") + std::strerror(errno));
  const std::string dir = std::filesystem::path(path_).parent_path().string();
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) ::fsync(dfd), ::close(dfd);
  ::close(fd_);
  fd_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0 || ::lseek(fd_, 0, SEEK_END) < 0)
    throw RuntimeError(path_, std::string("cannot reopen the journal: ") + std::strerror(errno));
  bytes_ = all.size();
  compacted_ = all.size();
}

uint64_t journal_run_id(const MissionParams& p) {
  return (static_cast<uint64_t>(p.seed) << 32) ^ (static_cast<uint64_t>(p.cycles) << 12) ^
         static_cast<uint64_t>(p.goals_per_request);
}

JournalKeeper::JournalKeeper(std::string path, int agent, uint64_t run) : journal_(std::move(path), agent, run) {}

JournalState JournalKeeper::open(bool replay) {
  JournalState s;
  if (replay)
    s = journal_.replay();
  else
    journal_.reset();
  return s;
}

void JournalKeeper::bind(Role& role) {
  role_ = &role;
  version_ = ~0ull;
  if (Custody* c = role.custody_log())
    c->enable_log(8 * kMaxBatch);  // a step's changes: a batch or two stored, a few acked
}

void JournalKeeper::snapshot(const MotionBackend& motion, double now) {
  state_.custody.clear();
  if (const Custody* c = role_->custody())
    for (std::size_t i = 0; i < c->size(); ++i) state_.custody.push_back(c->item(i));
  role_->progress(state_.progress);
  state_.have_progress = true;
  state_.pose = motion.pose(), state_.pose_t = now, state_.have_pose = true;
}

void JournalKeeper::after_step(const MotionBackend& motion, double now) {
  Custody* c = role_->custody_log();
  if (c && c->overflowed()) {
    // More changes than the log holds: the whole state, afresh.
    snapshot(motion, now);
    journal_.compact(state_);
    c->clear_changes();
    version_ = role_->progress_version();
    ++syncs_;
    return;
  }
  if (c) {
    for (const Custody::Change& ch : c->changes()) ch.put ? journal_.put(ch.item) : journal_.acked(ch.item);
    c->clear_changes();
  }
  if (role_->progress_version() != version_) {
    version_ = role_->progress_version();
    role_->progress(progress_);
    journal_.progress(progress_);
  }
  if (now >= next_pose_) {
    journal_.pose(motion.pose(), now);
    while (next_pose_ <= now) next_pose_ += 1.0;
  }
  if (journal_.sync()) ++syncs_;
  if (journal_.needs_compaction()) {
    snapshot(motion, now);
    journal_.compact(state_);
  }
}

}  // namespace agent
}  // namespace gather
