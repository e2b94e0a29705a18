#pragma once
// One agent's role and motion backend as the plan assigns them, for any
// runner: a worker drives a SimulatedBase, a collector follows its
// timetable, the OC stands at its station.
#include <memory>
#include <string>
#include <vector>

#include "gather_agent/motion/motion_backend.hpp"
#include "gather_agent/roles/oc_role.hpp"
#include "gather_agent/roles/role.hpp"
#include "gather_agent/transport/auth_counters.hpp"
#include "gather_agent/transport/range_gate.hpp"

namespace gather {
namespace agent {

struct AgentUnit {
  std::unique_ptr<MotionBackend> motion;
  std::unique_ptr<Role> role;
};

// Agent `agent` of team.plan, at its start pose (or at `at`: a restarted
// agent where it was). Throws gather::Error when the plan gives it no
// workable assignment.
AgentUnit make_agent(TeamSetup& team, AgentId agent, const Point2* at = nullptr);
// The OC at the scenario's OC position.
AgentUnit make_oc(TeamSetup& team);

// What one agent did in a run (`make run` prints it).
struct AgentSummary {
  int id = 0;
  RoleKind role = RoleKind::kWorker;
  RoleReport report;
  LinkCounters link;
  AuthCounters auth;      // over LCM: messages it dropped before decoding, by reason
  int64_t carried = 0;    // measured items in its custody at the end
  int64_t delivered = 0;  // items the OC accepted from it
};

// Every goal measured and stored is delivered or in some agent's custody
// (requested = delivered + carried + pending + expired + dropped, with
// carried counted from the custody buffers themselves): throws gather::Error
// ("conservation ...") naming the numbers when not. `custody` are the keys
// of every measured item any agent holds (duplicates allowed).
void check_conservation(const OcRole& oc, int64_t measured_total, std::vector<int32_t>& custody, double now);

}  // namespace agent
}  // namespace gather
