#pragma once
// The numeric range of every value that comes from outside: the fields of a
// scenario, a map YAML and plan.yaml, and every numeric flag of `gather` and
// `gather_agent` (docs/input_limits.md). They are declared here, once: the
// readers check a value with check_range(), `gather limits` lists them, and
// tests/cli/range_ends.py tries every one at both ends and just outside, so
// a range cannot be added without its ends being tried.
#include <cstdint>
#include <string>
#include <vector>

namespace gather {

// The memory [bytes] a command may take for any input inside these ranges
// (docs/input_limits.md, "Memory and time"): sizes that multiply are
// checked against it before anything is allocated for them.
constexpr double kMemoryBudget = 1024.0 * 1024.0 * 1024.0;

// Flags of a range.
enum : std::uint8_t {
  kRangeInt = 1,     // an integer
  kRangeOpenLo = 2,  // lo itself is refused
  kRangeOpenHi = 4,  // hi itself is refused
  kRangeZero = 8,    // 0 is accepted too (an "automatic" below the range)
  kRangeWork = 16,   // the time a command takes grows with the value (cycles, seeds, repeats)
};

// One range. `input`: "scenario", "map", "plan" (a file's fields; `key` is
// the YAML path, a list element as "oc[0]"), or the command that takes the
// flag ("gather run"; `key` is the flag). `coupled`: the rules between
// this value and others that can refuse a value inside the range; the error
// line of each holds one of these texts (separated by '|').
struct InputRange {
  const char* input;
  const char* key;
  double lo, hi;
  const char* unit;  // " m", " s", or ""
  std::uint8_t flags;
  const char* coupled;

  bool integer() const { return (flags & kRangeInt) != 0; }
  bool accepts(double v) const;
  // "[lo, hi] m" (with the open ends and "0 or ...").
  std::string text() const;
};

// Every range, in the order of the table below: (name, input, key, lo, hi, unit, flags, coupled).
// NOLINTBEGIN(cppcoreguidelines-macro-usage)
#define GATHER_INPUT_RANGES(X)                                                                               \
  X(kOcX, "scenario", "oc[0]", -1e7, 1e7, " m", 0, "outside the map|not free space")                         \
  X(kOcY, "scenario", "oc[1]", -1e7, 1e7, " m", 0, "outside the map|not free space")                         \
  X(kTeamAgents, "scenario", "team.agents", 1, 300, "", kRangeInt, "leaves no worker")                       \
  X(kTeamSpeed, "scenario", "team.speed", 0.01, 100, " m/s", 0, nullptr)                                     \
  X(kTeamRadius, "scenario", "team.radius", 0, 100, " m", 0, nullptr)                                        \
  X(kTxPower, "scenario", "radio.tx_power_dbm", -100, 100, " dBm", 0, "free-space range over 100 km")        \
  X(kRefLoss, "scenario", "radio.ref_loss_db", 0, 200, " dB", 0, "free-space range over 100 km")             \
  X(kExponent, "scenario", "radio.exponent", 0.5, 10, "", 0, "free-space range over 100 km")                 \
  X(kWallLoss, "scenario", "radio.wall_loss_db", 0, 200, " dB", 0, nullptr)                                  \
  X(kMaxWalls, "scenario", "radio.max_walls", 0, 100, "", kRangeInt, nullptr)                                \
  X(kSensitivity, "scenario", "radio.sensitivity_dbm", -200, 100, " dBm", 0, "free-space range over 100 km") \
  X(kBitrate, "scenario", "radio.bitrate_bps", 0, 1e12, " bit/s", 0, nullptr)                                \
  X(kGoalsPerRequest, "scenario", "mission.goals_per_request", 1, 5000, "", kRangeInt, "goal records")       \
  X(kCycles, "scenario", "mission.cycles", 1, 10000, "", kRangeInt | kRangeWork, "goal records")             \
  X(kPeriod, "scenario", "mission.period", 1, 1e5, " s", kRangeZero, nullptr)                                \
  X(kMissionSeed, "scenario", "mission.seed", 0, 2147483647, "", kRangeInt, nullptr)                         \
  X(kBytesPerGoal, "scenario", "mission.bytes_per_goal", 0, 1e9, " bytes", 0, nullptr)                       \
  X(kCollectorsMin, "scenario", "planner.collectors[0]", 0, 299, "", kRangeInt, "0 <= min <= max")           \
  X(kCollectorsMax, "scenario", "planner.collectors[1]", 0, 299, "", kRangeInt, "leaves no worker")          \
  X(kAlpha, "scenario", "planner.alpha", 0, 1e6, "", 0, nullptr)                                             \
  X(kBeta, "scenario", "planner.beta", 0, 1e6, "", 0, nullptr)                                               \
  X(kMaxCells, "scenario", "planner.max_cells", 10000, 1e12, "", kRangeInt | kRangeZero, nullptr)            \
  X(kResolution, "map", "resolution", 1e-4, 1e3, " m/cell", 0, "outside the map|not free space")             \
  X(kOriginX, "map", "origin[0]", -1e7, 1e7, " m", 0, "outside the map|not free space")                      \
  X(kOriginY, "map", "origin[1]", -1e7, 1e7, " m", 0, "outside the map|not free space")                      \
  X(kFreeThresh, "map", "free_thresh", 0, 1, "", 0, "thresholds out of order|not free space")                \
  X(kOccupiedThresh, "map", "occupied_thresh", 0, 1, "", 0, "thresholds out of order|not free space")        \
  X(kGridFactor, "plan", "grid_factor", 1, 1000, "", kRangeInt,                                              \
    "its labels are|not on free space of the planning grid")                                                 \
  X(kCyclePeriod, "plan", "cycle_period_s", 0, 1e5, " s", kRangeOpenLo, nullptr)                             \
  X(kAreaTile, "plan", "area_tile_m", 0, 1e6, " m", kRangeOpenLo, "a cell of the planning grid")             \
  X(kPlanSeedFlag, "gather plan", "--seed", 0, 2147483647, "", kRangeInt, nullptr)                           \
  X(kPlanThreads, "gather plan", "--threads", 1, 64, "", kRangeInt, nullptr)                                 \
  X(kSimCycles, "gather sim", "--cycles", 1, 10000, "", kRangeInt | kRangeWork, nullptr)                     \
  X(kSimSeeds, "gather sim", "--seeds", 1, 1000, "", kRangeInt | kRangeWork, nullptr)                        \
  X(kSimSeed, "gather sim", "--seed", 0, 2147483647, "", kRangeInt, nullptr)                                 \
  X(kSimThreads, "gather sim", "--threads", 1, 64, "", kRangeInt, nullptr)                                   \
  X(kRunCycles, "gather run", "--cycles", 1, 10000, "", kRangeInt | kRangeWork, nullptr)                     \
  X(kRunSeeds, "gather run", "--seeds", 1, 1000, "", kRangeInt | kRangeWork, nullptr)                        \
  X(kRunSeed, "gather run", "--seed", 0, 2147483647, "", kRangeInt, nullptr)                                 \
  X(kRunTick, "gather run", "--tick", 0.001, 0.1, " s", kRangeWork, nullptr)                                 \
  X(kRunLoss, "gather run", "--loss", 0, 0.999, "", 0, nullptr)                                              \
  X(kRunLossSeed, "gather run", "--loss-seed", 0, 2147483647, "", kRangeInt, nullptr)                        \
  X(kRunRate, "gather run", "--rate", 0, 1e6, "", kRangeWork, nullptr)                                       \
  X(kRunSpeedFactor, "gather run", "--speed-factor", 0.05, 1, "", 0, nullptr)                                \
  X(kRunSilentIntervals, "gather run", "--silent-intervals", 1.5, 100, "", 0, nullptr)                       \
  X(kKeygenKeyId, "gather keygen", "--key-id", 1, 32767, "", kRangeInt, nullptr)                             \
  X(kKeygenAgent, "gather keygen --agent", "--agent", 0, 1e6, "", kRangeInt, "is not in the plan")           \
  X(kReportWorkers, "gather partition --report", "--workers", 1, 1000, "", kRangeInt, nullptr)               \
  X(kReportRepeat, "gather partition --report", "--repeat", 1, 1000, "", kRangeInt | kRangeWork, nullptr)    \
  X(kReportSeed, "gather partition --report", "--seed", 0, 2147483647, "", kRangeInt, nullptr)               \
  X(kPartitionWorkers, "gather partition", "--workers", 1, 1000, "", kRangeInt, nullptr)                     \
  X(kPartitionSeed, "gather partition", "--seed", 0, 2147483647, "", kRangeInt, nullptr)                     \
  X(kFmmOrder, "gather fmm", "--order", 1, 2, "", kRangeInt, nullptr)                                        \
  X(kFmmRepeat, "gather fmm", "--repeat", 1, 1000, "", kRangeInt | kRangeWork, nullptr)                      \
  X(kFmmBucketWidth, "gather fmm", "--bucket-width", 0, 1e6, "", 0, nullptr)                                 \
  X(kFmmMaxTime, "gather fmm", "--max-time", 0, 1e15, "", 0, nullptr)                                        \
  X(kRadioRepeat, "gather radio", "--repeat", 1, 1000, "", kRangeInt | kRangeWork, nullptr)                  \
  X(kAgentId, "gather_agent", "--id", 0, 1e6, "", kRangeInt, "is not in the plan")                           \
  X(kAgentSilence, "gather_agent", "--silence", 0, 86400, " s", kRangeOpenLo | kRangeWork, nullptr)          \
  X(kAgentRobotSilence, "gather_agent", "--robot-silence", 0.2, 600, " s", kRangeWork, nullptr)              \
  X(kAgentTolerance, "gather_agent", "--waypoint-tolerance", 0.01, 10, " m", 0, nullptr)                     \
  X(kAgentClockSkew, "gather_agent", "--clock-skew", -3600, 3600, " s", 0, nullptr)                          \
  X(kBagViewPeriod, "mission_bag", "--view-period", 0.1, 3600, " s", 0, nullptr)
// NOLINTEND(cppcoreguidelines-macro-usage)

namespace range {
enum Id : std::size_t {
#define GATHER_RANGE_ID(name, ...) name,
  GATHER_INPUT_RANGES(GATHER_RANGE_ID)
#undef GATHER_RANGE_ID
      kCount
};
}  // namespace range

// The declared range `id`.
const InputRange& input_range(range::Id id);
// Every declared range, in declaration order.
const std::vector<InputRange>& input_ranges();

// Throws Error(where, "<key> = <v> must be in <range>") unless `v` is finite
// and in the range `id`.
void check_range(range::Id id, double v, const std::string& where);

}  // namespace gather
