#pragma once
// Who talks to whom in the fleet: the plan's links. Every agent is linked to
// the OC, and a worker of a collector to that collector (a repair never
// adds a link: it only moves workers to the OC). A message addressed to one
// receiver goes to it alone; a broadcast goes to its sender's links (the
// OC's: to every agent). This one rule decides which receivers a message is
// signed for (per-link keys, docs/security.md) and which messages a role
// hears, in one process and over LCM alike (gather_inbox).
#include <cstdint>
#include <vector>

namespace gather {
namespace agent {

class FleetLinks {
 public:
  FleetLinks() = default;
  // `upstream`, per agent 0..N-1: the agent id of its plan's collector, or
  // -1 (a collector, a worker of the OC). An id outside the team links to
  // nothing.
  explicit FleetLinks(std::vector<int16_t> upstream);

  int agents() const { return static_cast<int>(upstream_.size()); }
  // -1 (the OC) and agents 0..N-1 are ids here; anything else is linked to nothing.
  bool linked(int16_t a, int16_t b) const;
  // Whether `receiver` takes a message from `sender` addressed to `dest`
  // (an id, or kBroadcast): from one of its links, addressed to it or to
  // all. Never its own messages.
  bool hears(int16_t receiver, int16_t sender, int16_t dest) const;
  // Everyone who hears it (the OC first, then agents by id).
  void receivers(int16_t sender, int16_t dest, std::vector<int16_t>& out) const;
  // The links of `id` (the OC first, then agents by id).
  std::vector<int16_t> peers(int16_t id) const;
  const std::vector<int16_t>& upstream() const { return upstream_; }

 private:
  bool valid(int16_t id) const { return id >= -1 && id < agents(); }
  std::vector<int16_t> upstream_;
  std::vector<std::vector<int16_t>> downstream_;  // per agent: its workers (collectors)
};

}  // namespace agent
}  // namespace gather
