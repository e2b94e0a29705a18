#pragma once
// One agent's role and motion backend as the plan assigns them, for any
// runner: on ideal bases a worker drives a SimulatedBase and a collector a
// RouteBase; on robots both drive a RobotBase (the robot interface); the OC
// stands at its station.
#include <memory>
#include <string>
#include <vector>

#include "gather_agent/motion/motion_backend.hpp"
#include "gather_agent/motion/robot_base.hpp"
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
// agent where it was), on an ideal base; with `robot` set, on the robot
// behind the robot interface that receives its commands there. Throws
// gather::Error when the plan gives it no workable assignment.
AgentUnit make_agent(TeamSetup& team, AgentId agent, const Point2* at = nullptr, NavCommandSink* robot = nullptr,
                     const RobotBaseParams& robot_params = {});
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
  // On robots: what its robot reported (contacts with other robots) and the
  // robot link's counters; the first fault of its robot ("": none).
  int32_t contacts = 0;
  RobotLinkCounters robot;
  std::string robot_fault;
};

// An agent whose keys the OC revoked (docs/security.md, "Revocation"):
// when, the messages of it the OC dropped from then on, and its items the
// OC refused from others (OcRole::of_revoked).
struct Revocation {
  int agent = 0;
  double at = 0.0;  // [s]
  int64_t oc_refused = 0;
  int64_t oc_discarded = 0;
};
std::vector<Revocation> revocations(const OcRole& oc);
// `agent`'s among `revoked` (nullptr: it was not revoked).
const Revocation* revocation_of(const std::vector<Revocation>& revoked, int agent);
// "agent K's keys revoked at T s: ..." (gather run's and the OC node's line).
std::string describe(const Revocation& r);

// Every goal measured and stored is delivered or in some agent's custody, or
// was refused as a revoked agent's, and nothing is delivered or carried that
// nobody measured (requested = delivered + carried + pending + expired +
// dropped + lost, with carried counted from the custody buffers
// themselves): throws gather::Error ("conservation ...") naming the goal or
// the numbers when not. `measured`: by goal, how many workers measured and
// stored it (count_measured, from Role::measured_in_step); `custody`: the
// keys of every measured item any agent holds (duplicates allowed).
void check_conservation(const OcRole& oc, const std::vector<uint8_t>& measured, std::vector<int32_t>& custody,
                        double now);
void count_measured(std::vector<uint8_t>& measured, int32_t goal);

}  // namespace agent
}  // namespace gather
