#pragma once
// The whole team in one process: every role (the OC's included) on an
// in-memory bus, under the same range gate and the same lockstep clock as
// the multi-process fleet, without threads. Tick k is at t = k * tick: every
// motion backend advances to t, then every role steps with the messages
// sent in tick k - 1 (gated, in (sender, seq) order), and what they send is
// delivered in tick k + 1. A run ends when the OC has issued every request
// and every goal is resolved (delivered, expired or dropped), or at the time
// limit. Same plan, seed and tick: the same run, bit for bit, as the
// multi-process one (runner/lockstep.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "gather_agent/runner/journal.hpp"
#include "gather_agent/runner/robot_world.hpp"
#include "gather_agent/runner/team.hpp"
#include "gather_core/mission/simulator.hpp"

namespace gather {
namespace agent {

// An agent that dies at mission time `at` [s] (--kill ID@T): it stops at
// the first tick at or after `at`, keeping whatever it carried (in the
// multi-process fleet the OC sends its process SIGKILL then).
struct Kill {
  int agent = 0;
  double at = 0.0;
};
// Parses "ID@T" (agent id, mission time [s]); throws gather::Error naming
// `flag` when it is not that, or the id is not in 0..agents-1.
Kill parse_kill(const std::string& text, int agents, const std::string& flag);
// A comma-separated list of them ("" or "none": no kill), at most kMaxDead,
// each agent once.
std::vector<Kill> parse_kills(const std::string& list, int agents, const std::string& flag);

struct RunOptions {
  double tick = 0.1;  // [s] of mission time per tick (the control rate), (0, 0.1]
  double loss = 0.0;  // injected message loss probability, [0, 1)
  uint64_t loss_seed = 1;
  double time_limit = 0.0;   // [s] of mission time; 0: automatic (time_limit())
  std::size_t inbox = 1024;  // messages an agent takes per tick (the rest is counted as overflow)
  std::size_t outbox = 64;   // messages a role sends per tick
  std::vector<Kill> kills;   // agents to end during the run
  // Agents whose process crashes at `at` and is started again at once from
  // its journal (docs/faults.md, "Crash and restart"); needs journal_dir.
  std::vector<Kill> restarts;
  std::string journal_dir;  // every agent journals there ("": no journals)
  // The team on robots (not owned; nullptr: ideal bases): every agent drives
  // a RobotBase whose commands go to `robots`, stepped before the agents
  // every tick.
  RobotWorld* robots = nullptr;
  RobotBaseParams robot_params;
};

// Mission time after which an unfinished run stops: the requests, then
// room to drain (five periods and three loops of the longest route).
double time_limit(const TeamSetup& team);

struct RunOutcome {
  bool completed = false;  // every goal resolved
  std::string failure;     // why not
  int64_t ticks = 0;
  double end_s = 0.0;  // [s] mission time of the last tick
  double wall_ms = 0.0;
  mission::MissionResult result;     // when completed: accounting, metrics, per-cycle stats
  std::vector<AgentSummary> agents;  // by agent id
  LinkCounters oc_link;
  AuthCounters oc_auth;       // over LCM: what the OC dropped before decoding, by reason
  int64_t messages = 0;       // sent by everyone
  int64_t invalid_items = 0;  // items the OC could not place
  int64_t duplicate_items = 0;
  // Faults: agents the OC declared dead (id, when), by declaration; goals it
  // declared lost that a survivor resolved later; goals one agent gave up
  // (or the OC expired) that another measured, delivered (OcRole::open).
  std::vector<std::pair<int, double>> declared_dead;
  int64_t recovered = 0, overridden = 0;
  // Keys the OC revoked (MissionParams::revoke), in agent order.
  std::vector<Revocation> revoked;
  std::vector<Kill> kills;     // as asked (RunOptions::kills)
  std::vector<Kill> restarts;  // as asked (RunOptions::restarts)
  // In one process: (agent, measured items its journal gave back) per restart.
  std::vector<std::pair<int, int>> restored;
  // On robots: goals still owed at the time limit, closed as lost with
  // their agents (OcRole::close); 0 when every goal was resolved in time.
  int64_t closed_at_end = 0;
};

class TeamRunner {
 public:
  TeamRunner(TeamSetup& team, const RunOptions& options);
  ~TeamRunner();
  RunOutcome run();

  // For tests: the roles after (or during) a run.
  Role& role(AgentId agent);
  OcRole& oc();

  // One tick (run() calls it until done); public for tests that inspect
  // the roles in between. Returns false once the mission is over.
  bool tick();
  int64_t ticks() const { return ticks_; }
  // Tests: called around each agent's control step (motion advance, inbox,
  // role step), e.g. to count heap allocations there.
  void set_step_hooks(void (*before)(), void (*after)()) { before_ = before, after_ = after; }
  double now() const { return ticks_ * options_.tick; }

 private:
  TeamSetup& team_;
  RunOptions options_;
  RangeGate gate_;
  std::vector<AgentUnit> units_;  // [0] the OC, then agents 0..N-1
  std::vector<Outbox> outboxes_;
  std::vector<LinkCounters> links_;
  std::vector<uint32_t> seq_;
  std::vector<Message> sent_, next_;
  std::vector<const Message*> inbox_;
  std::vector<uint8_t> killed_;     // by unit
  std::vector<uint8_t> restarted_;  // by unit: restarted (once)
  std::vector<uint8_t> fresh_;      // by unit: restarted this tick (an empty inbox: a new process heard nothing yet)
  std::vector<std::unique_ptr<JournalKeeper>> journals_;  // by unit ([0], the OC's: none)
  // On robots: each agent's RobotBase (by agent id), the commands of the
  // tick, what the robots reported.
  std::vector<RobotBase*> robot_bases_;
  CommandQueue commands_;
  std::vector<NavCommand> sent_commands_;
  std::vector<RobotPose> poses_;
  std::vector<NavStatus> statuses_;
  void robots_step(double t);
  void restart(std::size_t unit, double t);
  std::vector<std::pair<int, int>> restored_;
  int64_t sent_before_restart_ = 0;
  int64_t ticks_ = 0;
  int next_check_ = 0;  // the next cycle end to check conservation at
  double limit_ = 0.0;
  std::vector<int32_t> custody_scratch_;
  std::vector<uint8_t> measured_;  // by goal: how many workers measured it (check_conservation)
  void (*before_)() = nullptr;
  void (*after_)() = nullptr;
};

// Once the OC has declared an agent dead, some goals it declared lost may
// still be resolved by a survivor: a live worker that still has goals to
// measure, or has not yet learned (or skipped) the last request, still owes
// the OC news, and the mission is not over.
bool still_owes(const RoleReport& worker, const OcRole& oc);

// Conservation over a team in one process (custody read from the roles,
// the dead ones' included).
void check_team_conservation(const OcRole& oc, const std::vector<AgentUnit>& agents,
                             const std::vector<uint8_t>& measured, double now, std::vector<int32_t>& scratch);

// At the end of a run in one process, where the ground truth is at hand:
// every goal the OC declared lost with an agent was in the custody of an
// agent that died (or retired), or was one of a dead worker's own; throws
// gather::RuntimeError otherwise. `roles` and `gone` (the dead or retired)
// by agent id.
void check_lost_goals(const OcRole& oc, const std::vector<const Role*>& roles, const std::vector<uint8_t>& gone);

// The summaries of a run, by agent id.
std::vector<AgentSummary> summarize(const OcRole& oc, const std::vector<const Role*>& roles,
                                    const std::vector<LinkCounters>& links);

}  // namespace agent
}  // namespace gather
