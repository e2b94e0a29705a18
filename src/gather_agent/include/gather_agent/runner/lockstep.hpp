#pragma once
// The team over LCM, one process per agent, on the OC's lockstep clock.
//
// Before the mission the OC announces the plan (its digest and the mission
// parameters) until every agent replied READY (its own copy of the plan has
// the same digest) or one REFUSED. Then, tick after tick (t = k * tick):
//   1. the OC publishes tick k with the number of radio messages sent in
//      tick k - 1 by everyone;
//   2. every agent (and the OC's own role) waits until it has received all
//      of them, advances its motion to t, takes those messages through the
//      range gate in (sender, seq) order, steps its role, publishes what it
//      sends (tagged k) and replies (what it sent, its pose and counters);
//   3. the next tick starts when every agent has replied (or after a
//      timeout, reported as an error naming the agent).
// The inbox of a tick is the same set in the same order whatever the
// arrival order or the load, so a run is the in-process run (TeamRunner),
// bit for bit.
//
// Wall-clock mode (for real robots; MasterOptions::clock): after the plan
// the OC announces the wall time of the mission's start; every process then
// steps its role every tick / rate seconds of wall time with whatever
// arrived meanwhile, mission time = wall time since the start x rate. The
// wall time is the fleet's (the OC's clock): each agent measures its host's
// offset to it (transport/fleet_clock.hpp) before anything else. No ticks,
// no replies, no per-agent counters at the OC, not reproducible.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "gather_agent/runner/journal.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/runner/team.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_agent/shutdown_signal.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"
#include "gather_agent/transport/lcm_robot.hpp"

namespace gather {
namespace agent {

// FNV-1a 64 over the bytes of everything a run depends on: plan.yaml, its
// labels image, the scenario, its map YAML and image. Throws gather::Error
// naming a file it cannot read.
uint64_t plan_digest(const LoadedPlan& plan);

// One agent process: its role, its motion, the radio and the clock.
class LockstepAgent {
 public:
  // `plan` must outlive the agent. Once its role is built, the agent drops
  // the plan's label image (only the OC needs it; its role keeps its own
  // segment): 4 B/cell less resident memory. `robot` (optional, must
  // outlive the agent): the robot interface's link (gather_agent --motion
  // lcm): the agent drives a RobotBase (`robot_params`) through it, says
  // READY only once its robot has reported, and on the lockstep clock takes
  // its robot's report of each tick before it steps.
  LockstepAgent(LoadedPlan& plan, int id, LcmFleet& fleet, LcmRobotLink* robot = nullptr,
                const RobotBaseParams& robot_params = {});
  // Journals what it carries in `dir` (runner/journal); `rejoin`: this
  // process restarts a crashed one: it replays the journal and joins the
  // mission under way (its first tick with nothing heard yet). Before run().
  void set_journal(const std::string& dir, bool rejoin);
  ~LockstepAgent();

  enum class End { kDone, kStopped, kRefused, kSilent };
  // Runs until the OC ends the mission (kDone), SIGINT/SIGTERM (kStopped),
  // the OC's plan differs from this agent's (kRefused: `why` says how), or
  // nothing was heard from the OC for `silence_s` seconds (kSilent).
  End run(ShutdownSignal& signal, double silence_s, std::string* why);

 private:
  bool take_plan(std::string* why);
  // The robot's messages: held by tick (lockstep), or taken at `now` (wall clock).
  void absorb_robot();
  bool robot_reported(int64_t tick) const;
  void feed_robot(int64_t tick, double now);
  void report_fault(double now);
  void step(const Tick& tick);
  void step_wall(double t);
  bool inbox_complete(const Tick& tick) const;

  LoadedPlan& plan_;
  int id_;
  LcmFleet& fleet_;
  uint64_t digest_;
  std::unique_ptr<mission::World> world_;
  std::unique_ptr<TeamSetup> team_;
  std::unique_ptr<RangeGate> gate_;
  AgentUnit unit_;
  std::unique_ptr<Outbox> outbox_;
  LinkCounters link_;
  uint32_t seq_ = 0;
  int64_t next_tick_ = 0;
  int64_t late_ = 0;
  int64_t incomplete_ = 0;
  int64_t step_us_ = 0;
  double tick_s_ = 0.1;
  ClockMode clock_ = ClockMode::kLockstep;
  double rate_ = 1.0;
  int64_t wall_start_us_ = 0;  // wall clock: the mission's start
  double wall_next_ = 0.0;     // [s] mission time of the next wall-clock step
  int wall_wait_ms_ = 20;
  std::vector<Message> held_;     // radio messages of ticks not yet processed
  std::vector<Message> current_;  // the messages of the tick being processed
  std::vector<const Message*> inbox_;
  Reply reply_;
  std::vector<int32_t> unreported_;  // goals measured, not yet in a reply (at most kReplyMaxPoints a reply)
  std::string journal_dir_;
  bool rejoin_ = false;
  std::unique_ptr<JournalKeeper> journal_;
  JournalState rejoin_state_;  // restored at the first tick, at that tick's time (as in one process)
  // The robot (--motion lcm).
  LcmRobotLink* robot_ = nullptr;
  RobotBaseParams robot_params_;
  RobotBase* base_ = nullptr;  // unit_.motion, when on a robot
  std::vector<RobotPose> robot_poses_;
  std::vector<NavStatus> robot_statuses_;
  bool robot_heard_ = false, waiting_said_ = false;
  bool offset_said_ = false;  // its clock offset to the OC printed
  BaseFault fault_said_ = BaseFault::kNone;
};

// How long the OC waits for the READY of agents it did not start (on the
// robots: gather run --agents external) [s].
constexpr double kExternalReadyTimeout_s = 300.0;

struct MasterOptions {
  ClockMode clock = ClockMode::kLockstep;  // kWall: no ticks; mission time is wall time x rate
  double tick = 0.1;                       // [s] of mission time per tick (wall clock: per control step)
  double loss = 0.0;                       // injected loss of the range gate
  uint64_t loss_seed = 1;
  double rate = 0.0;              // times real time (0: as fast as the lockstep allows; the wall clock needs > 0)
  double ready_timeout_s = 60.0;  // for every agent to say READY
  double reply_timeout_s = 10.0;  // for every agent to reply to a tick
  double time_limit = 0.0;        // [s] of mission time; 0: time_limit(team)
  int64_t start_us = 0;           // wall clock: the mission's start [us since the epoch]; 0: 0.2 s after READY
  // The agents drive robots through the robot interface (gather_agent
  // --motion lcm): with the lockstep clock each waits for its robot's
  // report of every tick, and gather_world for the tick before's commands.
  bool robots = false;
  bool observe = false;  // keep ViewEvents for take_events() (the OC's views)
  // Agents to end (SIGKILL to the pid each said READY with; lockstep only).
  std::vector<Kill> kills;
  // Agents whose process is killed and started again (lockstep only): the
  // OC sends SIGKILL, calls `respawn` (which starts it with --rejoin, or
  // leaves that to fleet_node), waits for its READY and goes on.
  std::vector<Kill> restarts;
  std::function<void(int)> respawn;
  // Ends agent k's process (for kills and restarts); unset: SIGKILL to the
  // pid it said READY with (an agent on the same host).
  std::function<void(int)> kill_agent;
  // The agents whose process ended since the last call, with its exit
  // status (128 + signal when killed); unset: the OC cannot see them (not
  // its children). One that ends while the OC waits for its READY or its
  // reply (and was not ended by the OC) stops the mission at once, naming
  // the agents and their status, instead of after the timeout.
  std::function<std::vector<std::pair<int, int>>()> ended;
};

// What views of the mission need beyond the agents' last replies (kept only
// with MasterOptions::observe, until take_events()).
struct MeasuredEvent {
  int32_t goal = 0;
  int16_t agent = 0;
  double t = 0.0;  // [s] the tick it was reported in
};
struct HandoverEvent {
  int16_t from = 0, to = 0;  // custody of `items` items passed from -> to (kOc: the OC)
  uint16_t items = 0;
  double t = 0.0;
};
struct ViewEvents {
  std::vector<MeasuredEvent> measured;
  std::vector<HandoverEvent> handovers;
};

// The OC's side: announces the plan, drives the clock, runs the OC role.
class LockstepMaster {
 public:
  LockstepMaster(TeamSetup& team, LcmFleet& fleet, uint64_t digest, const MasterOptions& options);
  ~LockstepMaster();

  // Announces the plan until every agent is READY. Throws gather::Error
  // naming the agents that refused or stayed silent. `signal` (optional)
  // aborts the wait.
  void start(ShutdownSignal* signal);
  // One tick; false once the mission is over (every goal resolved, or the
  // time limit). Throws gather::Error when an agent does not reply in time.
  bool tick(ShutdownSignal* signal);
  // Ends the mission (the agents stop) and returns what happened.
  RunOutcome finish();

  int64_t ticks() const { return tick_; }
  double now() const { return options_.clock == ClockMode::kWall ? wall_now_ : tick_ * options_.tick; }
  // Mission time [s] of the last tick run (what agents() and the OC's ledger
  // describe); 0 before the first.
  double last_tick_time() const {
    return options_.clock == ClockMode::kWall ? wall_now_ : tick_ > 0 ? (tick_ - 1) * options_.tick : 0.0;
  }
  OcRole& oc() { return static_cast<OcRole&>(*oc_.role); }
  // The last reply of each agent (pose, role, counters, planned path), by
  // agent id. With the wall clock there are no replies: the pose, role and
  // counters of the last radio message heard from it.
  const std::vector<Reply>& agents() const { return last_; }
  // Moves the events since the last call into `into` (MasterOptions::observe).
  void take_events(ViewEvents& into);
  const MasterOptions& options() const { return options_; }
  int64_t messages() const { return messages_; }
  // Wall time spent waiting for replies, running the OC role, pacing [ms].
  double wait_ms() const { return wait_ms_; }
  double oc_ms() const { return oc_ms_; }
  double publish_ms() const { return publish_ms_; }  // publishing the ticks
  double inbox_ms() const { return inbox_ms_; }      // the OC waiting for the previous tick's messages
  // The agents' control steps so far, summed over the agents [ms of CPU].
  double agents_step_ms() const;

 private:
  void collect_replies(int64_t tick, ReplyStatus want, double timeout_s, ShutdownSignal* signal);
  bool tick_wall(ShutdownSignal* signal);
  void observe(double t, bool wall);
  // Killed by the lockstep, or declared dead by the OC: its custody no
  // longer holds the mission's end.
  bool gone(int agent) const { return killed_[static_cast<std::size_t>(agent)] || oc_role_dead(agent); }
  bool oc_role_dead(int agent) const;

  TeamSetup& team_;
  LcmFleet& fleet_;
  uint64_t digest_;
  MasterOptions options_;
  RangeGate gate_;
  AgentUnit oc_;
  Outbox outbox_;
  LinkCounters link_;
  uint32_t seq_ = 0;
  int64_t tick_ = 0;
  int32_t sent_before_ = 0;
  std::vector<int32_t> expect_;     // per agent: what it is to receive of the tick before's messages
  std::vector<int16_t> receivers_;  // scratch (FleetLinks::receivers)
  int32_t commands_before_ = 0;     // navigation commands the agents sent in the tick before (robots)
  int next_check_ = 0;
  double limit_ = 0.0;
  int64_t messages_ = 0;
  std::vector<Reply> last_;
  std::vector<uint8_t> replied_;
  std::vector<uint8_t> killed_;
  std::vector<uint8_t> restarted_;
  // Agents whose process ended while a reply was owed (MasterOptions::ended),
  // seen since: the run stops kEndedGrace_s later if they still owe it.
  static constexpr double kEndedGrace_s = 0.5;
  bool ended_seen_ = false;
  std::chrono::steady_clock::time_point ended_seen_at_;
  std::vector<int32_t> pid_;
  void restart(int agent, ShutdownSignal* signal);
  std::vector<Message> held_, current_;
  std::vector<const Message*> inbox_;
  std::vector<int32_t> keys_;
  std::vector<uint8_t> measured_;  // by goal: how many workers measured it (check_conservation)
  ViewEvents events_;
  std::chrono::steady_clock::time_point started_;
  double wait_ms_ = 0.0, oc_ms_ = 0.0, publish_ms_ = 0.0, inbox_ms_ = 0.0;
  bool finished_ = false;
  // Wall clock.
  int64_t start_us_ = 0;
  double wall_now_ = 0.0, done_at_ = -1.0;
  std::chrono::steady_clock::time_point clock_said_;
};

}  // namespace agent
}  // namespace gather
