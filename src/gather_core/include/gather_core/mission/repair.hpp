#pragma once
// Plan repair after agents die, and when the OC declares an agent dead
// (docs/faults.md). The survivors' plan is a pure function of the original
// plan and the set of agents declared dead: every agent that knows the same
// set executes the same plan, and only the set travels over the radio.
#include <cstdint>
#include <string>
#include <vector>

#include "gather_core/mission/mission_plan.hpp"

namespace gather {
namespace mission {

// What becomes of a dead worker's segment.
enum class RepairMode : uint8_t {
  kMerge,  // the surviving worker of the adjacent segment with the fewest cells serves it too
  kNone,   // nobody serves it: its goals expire (the baseline repair is measured against)
};
const char* repair_mode_name(RepairMode m);
// "merge" | "none"; throws gather::Error naming `where` otherwise.
RepairMode parse_repair_mode(const std::string& text, const std::string& where);

// The plan the survivors execute once the agents in `dead` (ids, any order,
// duplicates ignored) are dead:
// - a dead worker's segment (kMerge) is relabelled as the segment of the
//   surviving worker whose segment touches it (4-neighbour) and has the
//   fewest labelled cells (ties: the lower segment), in passes over the
//   dead workers (by id) until none merges: a segment whose neighbours are
//   all dead merges once one of them has merged into a live one; a segment
//   merged before moves as a whole. A segment with no surviving neighbour
//   then, or kNone: relabelled 0 (no segment: its goals expire at the next
//   request);
// - the workers of a dead collector deliver to the OC;
// - dead agents keep their entries in plan.file.agents (ids stay 0..N-1);
//   `dead` flags them.
// `base` must hold its label image (labels.filled(): not released).
struct RepairedPlan {
  MissionPlan plan;
  PerAgent<uint8_t> dead;                 // 1: dead
  PerSegment<AgentId> worker_of_segment;  // by original segment; none: nobody
};
RepairedPlan repair_plan(const MissionPlan& base, const std::vector<AgentId>& dead, RepairMode mode);

// How long the OC waits without news of an agent before it declares it
// dead [s] (docs/faults.md, "Liveness"): `intervals` times the longest a
// live agent goes unheard by the protocol: a collector passes the OC once a
// loop (`route_period` [s]); a worker of the OC is back in the coverage
// once a request (`period` [s]); a collector's worker meets its collector
// once a request and the collector reports it at its next OC pass
// (route_period + period).
enum class Liveness : uint8_t { kCollector, kOcWorker, kCollectorWorker };
double silent_timeout(Liveness kind, double period, double route_period, double intervals);

}  // namespace mission
}  // namespace gather
