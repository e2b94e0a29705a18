#pragma once
// Per-agent keys and the plan (docs/security.md): an agent's key file holds
// the keys of the links its plan gives it, derived from the OC's master.
#include <string>
#include <vector>

#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_core/plan/plan_file.hpp"

namespace gather {
namespace agent {

// Agent `agent`'s keys for `plan` (its links: the OC, and its collector or
// its workers).
KeyRing agent_keys_for(const FleetKey& master, int agent, const plan::PlanFile& plan);

// The keys agent `id` runs with against its plan: an agent's file must be
// agent `id`'s, under the plan's links exactly (else gather::Error naming
// `path`). The master is taken too (the caller warns: whoever takes the
// robot holds every key; master_warning).
void check_agent_keys(const KeyRing& keys, const std::string& path, int id, const plan::PlanFile& plan);
// The warning an agent prints when it holds the master (one line, no newline).
std::string master_warning(const std::string& path, int id);

// Writes every agent's key file of `plan` into `dir` (made if missing,
// mode 0700) as agent-K.key (mode 0600; an existing file is replaced: the
// directory is the run's own). Returns the paths, by agent.
std::vector<std::string> write_agent_keys(const FleetKey& master, const plan::PlanFile& plan, const std::string& dir);

}  // namespace agent
}  // namespace gather
