#pragma once
// An agent's on-disk journal: what it carries (custody) and how far it got
// (Progress, its pose), so that a process that crashed and is started again
// hands over everything it held (docs/faults.md, "Crash and restart").
//
// One file per agent, append-only: a header (format, agent id, the run it
// belongs to), then records [u32 payload size][u32 CRC-32 of type and
// payload][u8 type][payload]: an item stored, a key acked away, a progress
// snapshot, a pose; each control step's records go in one batch record (one
// CRC: a step comes back whole or not at all), appended with one write()
// and made durable with fdatasync() before the step's messages go out. Bounded: past kCompactBytes the file is
// rewritten (to a temporary file, fsync, rename) with the current state only. On start, the records are replayed up to
// the first one that is torn or fails its CRC (a crash during a write), and the file is cut there.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gather_agent/messages.hpp"
#include "gather_agent/motion/motion_backend.hpp"
#include "gather_agent/roles/role.hpp"

namespace gather {
namespace agent {

// What a journal holds after replay.
struct JournalState {
  std::vector<DataItem> custody;  // in the order stored, acked ones removed
  Progress progress;
  bool have_progress = false;
  bool have_pose = false;
  Point2 pose;              // [m] the last one journaled
  double pose_t = 0.0;      // [s] when
  std::size_t records = 0;  // good records read
  bool cut = false;         // a torn or corrupt tail was cut off
  bool matched = false;     // the file was this agent's of this run (else it was started afresh)
};

class Journal {
 public:
  static constexpr std::size_t kCompactBytes = 256 * 1024;

  // Opens (creates) `path` for agent `agent` of run `run` (any number that
  // identifies the mission: a journal of another run is not replayed).
  // Throws gather::Error naming the file when it cannot.
  Journal(std::string path, int agent, uint64_t run);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  // Reads what the file holds (empty for a new file or another run's, which
  // is started afresh).
  JournalState replay();
  // Starts the file afresh (a new mission).
  void reset();

  void put(const DataItem& item);
  void acked(const DataItem& item);
  void progress(const Progress& p);
  void pose(Point2 at, double t);  // at [m], mission time t [s]
  // Writes what was appended since the last sync, and makes it durable
  // (fdatasync) when it holds more than poses (a pose may be lost in a power
  // cut; a process crash keeps what was written). False when nothing was
  // pending.
  bool sync();
  // Rewrites the file with `state` only (its custody, progress and pose).
  void compact(const JournalState& state);
  std::size_t bytes() const { return bytes_; }
  // Past kCompactBytes and twice the size of the last compaction (a state
  // larger than the bound is not rewritten every step).
  bool needs_compaction() const { return bytes_ > kCompactBytes && bytes_ > 2 * compacted_; }
  const std::string& path() const { return path_; }

 private:
  void record(uint8_t type, const void* payload, std::size_t n);
  void write_all(int fd, const uint8_t* data, std::size_t n);
  void header(std::vector<uint8_t>& out) const;

  std::string path_;
  int agent_;
  uint64_t run_;
  int fd_ = -1;
  std::size_t bytes_ = 0;         // in the file
  std::vector<uint8_t> pending_;  // appended, not yet written
  bool durable_ = false;          // pending_ holds more than poses
  std::vector<uint8_t> scratch_;
  std::vector<uint8_t> batch_;
  std::size_t compacted_ = 0;  // bytes right after the last compaction
};

// Keeps a role's journal up to date after each control step (the runner
// calls it; roles do no I/O): custody changes, its progress when it
// changed, its pose once a second of mission time; durable before the
// step's messages are sent. Allocates only when compacting.
class JournalKeeper {
 public:
  JournalKeeper(std::string path, int agent, uint64_t run);
  // What the previous life of this agent left (`replay`: for
  // Role::restore), or a fresh journal. Call once, first.
  JournalState open(bool replay);
  // The role it journals (enables its custody log).
  void bind(Role& role);
  void after_step(const MotionBackend& motion, double now);  // now: mission time [s]
  Journal& journal() { return journal_; }
  int64_t syncs() const { return syncs_; }

 private:
  void snapshot(const MotionBackend& motion, double now);

  Journal journal_;
  Role* role_ = nullptr;
  uint64_t version_ = ~0ull;
  double next_pose_ = 0.0;
  Progress progress_;
  JournalState state_;
  int64_t syncs_ = 0;
};

// The journal file of `agent` in `dir`.
std::string journal_path(const std::string& dir, int agent);
// What identifies a mission's journals (its seed, cycles, goals a request).
uint64_t journal_run_id(const MissionParams& params);

}  // namespace agent
}  // namespace gather
